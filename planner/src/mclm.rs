//! MCLM, Motion Coordinated Linear Move: a straight line through the axes of
//! a coordinate system, the companion of [`crate::mccm`] that real programs
//! blend with arcs.
//!
//! The operands are MCCM's without Circle Type, Via/Center/Radius and
//! Direction ([`CoordMoveInputs`]); their meaning, units, termination,
//! merge, master-driven and event rules are those of the
//! [`crate::coord`] module. ERR 13 EXERR indices follow MCLM's faceplate
//! ([`OperandIndex::MCLM`]): 0 coordinate system, 2 move type, 3 position,
//! 4 speed, 6 accel, 8 decel, 11 termination type, …
//!
//! # Choices where the spec is silent
//! * A system of 1 to 3 primary axes can make linear moves (MCCM needs 2 or 3).
//! * A move whose end equals its start is legal: it completes at once
//!   (termination type 0 still waits for the actual tolerance).
//! * Positions so large that the distance overflows are ERR 13, EXERR 3.

use crate::coord::{
    CoordMove, CoordMoveError, CoordMoveInputs, MoveContext, OperandIndex, PathGeometry, finish_move,
    resolve_move_type_and_position,
};

/// MCLM: verifies the operands and builds the line.
///
/// # Errors
/// [`CoordMoveError`]: 13 (operand index, [`OperandIndex::MCLM`]) and 54.
pub fn mclm(inputs: &CoordMoveInputs, ctx: &MoveContext<'_>) -> Result<CoordMove, CoordMoveError> {
    let idx = OperandIndex::MCLM;
    let resolved = resolve_move_type_and_position(inputs, ctx, &idx)?;
    let primary = ctx.system.config().primary_axes;
    finish_move(inputs, ctx, &idx, || {
        let path = PathGeometry::line(resolved.start, resolved.end, primary);
        if path.length().is_finite() {
            Ok(path)
        } else {
            // Coordinates so large that the distance overflows.
            Err(crate::coord::out_of_range(idx.position))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coord::{CoordinateSystem, CoordinateSystemConfig};
    use crate::dynamics::MoveDynamics;
    use crate::instruction::LogixFault;

    fn system() -> CoordinateSystem {
        CoordinateSystem::new(CoordinateSystemConfig {
            axis_count: 4,
            primary_axes: 3,
            max_speed: 100.0,
            max_accel: 1000.0,
            max_decel: 1000.0,
            ..CoordinateSystemConfig::new("CS")
        })
        .unwrap()
    }

    fn run(inputs: &CoordMoveInputs) -> Result<CoordMove, (i32, i32)> {
        let sys = system();
        let ctx = MoveContext {
            system: &sys,
            axis_max_decel: &[1.0; 4],
            start: &[1.0, 2.0, 3.0, 4.0],
            has_master: false,
        };
        mclm(inputs, &ctx).map_err(|e| (e.err(), e.exerr()))
    }

    fn ok() -> CoordMoveInputs {
        CoordMoveInputs {
            position: vec![4.0, 6.0, 3.0, 10.0],
            dynamics: MoveDynamics {
                speed: 10.0,
                accel_rate: 100.0,
                decel_rate: 100.0,
                ..CoordMoveInputs::default().dynamics
            },
            ..Default::default()
        }
    }

    #[test]
    fn absolute_and_incremental_end_points() {
        let m = run(&ok()).unwrap();
        assert_eq!(m.path().end(), &[4.0, 6.0, 3.0, 10.0]);
        assert_eq!(m.path().length(), 5.0, "only the primary axes count");
        let m = run(&CoordMoveInputs { move_type: 1, ..ok() }).unwrap();
        assert_eq!(m.path().end(), &[5.0, 8.0, 6.0, 14.0]);
    }

    #[test]
    fn non_primary_axes_move_with_the_path_fraction() {
        let m = run(&ok()).unwrap();
        let (mut p, mut d) = ([0.0; 4], [0.0; 4]);
        m.path().point(2.5, &mut p, &mut d);
        assert_eq!(p, [2.5, 4.0, 3.0, 7.0]);
        // Only the non-primary axis moves: its distance is the path length.
        let only = CoordMoveInputs {
            position: vec![1.0, 2.0, 3.0, 1.0],
            ..ok()
        };
        assert_eq!(run(&only).unwrap().path().length(), 3.0);
    }

    #[test]
    fn every_parameter_error_names_its_operand() {
        let cases: Vec<(CoordMoveInputs, i32)> = vec![
            (CoordMoveInputs { move_type: 2, ..ok() }, 2),
            (
                CoordMoveInputs {
                    position: vec![1.0; 3],
                    ..ok()
                },
                3,
            ),
            (
                CoordMoveInputs {
                    position: vec![1.0, f64::NAN, 1.0, 1.0],
                    ..ok()
                },
                3,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        speed: -1.0,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                4,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        speed_units: 3,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                5,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        accel_rate: 0.0,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                6,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        accel_units: 9,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                7,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        decel_rate: -2.0,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                8,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        decel_units: 4,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                9,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        profile: 2,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                10,
            ),
            (
                CoordMoveInputs {
                    termination_type: 7,
                    ..ok()
                },
                11,
            ),
            (
                CoordMoveInputs {
                    termination_type: -1,
                    ..ok()
                },
                11,
            ),
            (CoordMoveInputs { merge: 3, ..ok() }, 12),
            (CoordMoveInputs { merge_speed: 2, ..ok() }, 13),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        profile: 1,
                        accel_jerk: 0.0,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                14,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        profile: 1,
                        decel_jerk: 101.0,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                15,
            ),
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        profile: 1,
                        jerk_units: 4,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                16,
            ),
            (
                CoordMoveInputs {
                    termination_type: 6,
                    command_tolerance: -1.0,
                    ..ok()
                },
                17,
            ),
            (
                CoordMoveInputs {
                    lock_direction: 5,
                    ..ok()
                },
                19,
            ),
            (
                CoordMoveInputs {
                    event_distance: vec![1.0, -1.0],
                    ..ok()
                },
                20,
            ),
            // Master-driven on a system without a master.
            (
                CoordMoveInputs {
                    dynamics: MoveDynamics {
                        speed_units: 4,
                        accel_units: 4,
                        decel_units: 4,
                        ..ok().dynamics
                    },
                    ..ok()
                },
                5,
            ),
        ];
        for (inputs, exerr) in cases {
            assert_eq!(run(&inputs).map(|_| ()), Err((13, exerr)), "{inputs:?}");
        }
        // Trapezoidal moves ignore the jerk operands.
        assert!(
            run(&CoordMoveInputs {
                dynamics: MoveDynamics {
                    accel_jerk: -5.0,
                    ..ok().dynamics
                },
                ..ok()
            })
            .is_ok()
        );
    }

    #[test]
    fn max_decel_zero_names_the_axis_or_the_system() {
        let sys = system();
        let ctx = MoveContext {
            system: &sys,
            axis_max_decel: &[1.0, 1.0, 0.0, 1.0],
            start: &[0.0; 4],
            has_master: false,
        };
        assert_eq!(
            mclm(&ok(), &ctx).map(|_| ()).map_err(|e| (e.err(), e.exerr())),
            Err((54, 2))
        );
        let zero = CoordinateSystem::new(CoordinateSystemConfig {
            axis_count: 4,
            max_decel: 0.0,
            ..CoordinateSystemConfig::new("Z")
        })
        .unwrap();
        let ctx = MoveContext { system: &zero, ..ctx };
        // % of maximum of a zero maximum is an operand error first…
        let pct = CoordMoveInputs {
            dynamics: MoveDynamics {
                decel_units: 1,
                decel_rate: 100.0,
                ..ok().dynamics
            },
            ..ok()
        };
        assert_eq!(
            mclm(&pct, &ctx).map(|_| ()).map_err(|e| (e.err(), e.exerr())),
            Err((13, 8))
        );
        // …a rate in units/s² reaches the check of the system's maximum.
        assert_eq!(
            mclm(&ok(), &ctx).map(|_| ()).map_err(|e| (e.err(), e.exerr())),
            Err((54, -1))
        );
    }

    #[test]
    fn percent_of_maximum_and_calculated_data() {
        let inputs = CoordMoveInputs {
            event_distance: vec![0.0, 5.0, 100.0],
            dynamics: MoveDynamics {
                speed: 10.0,
                speed_units: 1,
                accel_rate: 1.0,
                accel_units: 1,
                decel_rate: 1.0,
                decel_units: 1,
                ..ok().dynamics
            },
            ..ok()
        };
        let m = run(&inputs).unwrap();
        let l = m.limits().unwrap();
        assert_eq!((l.velocity(), l.acceleration(), l.deceleration()), (10.0, 10.0, 10.0));
        // 5 units with 10 units/s² never reach 10 units/s: a triangle, t = 2·√(2·2.5/10) = √2 s.
        let cd = m.calculated_data();
        assert!((cd[0] - std::f64::consts::SQRT_2).abs() < 1e-6, "{cd:?}");
        assert!(cd[1].abs() < 1e-12 && cd[2] == 0.0, "{cd:?}");
    }
}
