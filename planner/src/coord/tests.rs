use super::*;
use crate::instruction::LogixFault;

#[test]
fn system_validation_names_the_field() {
    let ok = CoordinateSystemConfig::new("CS");
    assert!(CoordinateSystem::new(ok.clone()).is_ok());
    for primary in [0, 4] {
        let c = CoordinateSystemConfig {
            primary_axes: primary,
            ..ok.clone()
        };
        assert!(matches!(
            CoordinateSystem::new(c),
            Err(CoordConfigError::PrimaryAxes { .. })
        ));
    }
    let c = CoordinateSystemConfig {
        axis_count: 2,
        ..ok.clone()
    };
    assert!(matches!(
        CoordinateSystem::new(c),
        Err(CoordConfigError::PrimaryAxes { .. })
    ));
    let c = CoordinateSystemConfig {
        max_speed: 0.0,
        ..ok.clone()
    };
    assert!(matches!(
        CoordinateSystem::new(c),
        Err(CoordConfigError::Field { field: "max_speed", .. })
    ));
    let c = CoordinateSystemConfig {
        command_tolerance: f64::NAN,
        ..ok.clone()
    };
    assert!(matches!(
        CoordinateSystem::new(c),
        Err(CoordConfigError::Field {
            field: "command_tolerance",
            ..
        })
    ));
    // A zero maximum deceleration is a configuration Logix accepts (error 54 at the move).
    let c = CoordinateSystemConfig { max_decel: 0.0, ..ok };
    assert!(CoordinateSystem::new(c).is_ok());
}

#[test]
fn status_bits_by_name() {
    let s = CoordStatus {
        move_pending: true,
        ..Default::default()
    };
    assert_eq!(s.bit("MovePendingStatus"), Some(true));
    assert_eq!(s.bit("motionstatus"), Some(false));
    assert_eq!(s.bit("Nope"), None);
    assert_eq!(s.bits().len(), 11);
}

#[test]
fn mcs_errors() {
    let sys = CoordinateSystem::new(CoordinateSystemConfig::new("CS")).unwrap();
    let e = |i: McsInputs| Mcs::new(&i, &sys).map(|_| ()).map_err(|e| (e.err(), e.exerr()));
    let d = McsInputs::default();
    assert_eq!(e(McsInputs { stop_type: 3, ..d }), Err((13, 2)));
    assert_eq!(e(McsInputs { change_decel: 2, ..d }), Err((13, 3)));
    assert_eq!(
        e(McsInputs {
            change_decel: 1,
            decel_rate: 0.0,
            ..d
        }),
        Err((13, 4))
    );
    assert_eq!(
        e(McsInputs {
            change_decel: 1,
            decel_units: 7,
            ..d
        }),
        Err((13, 5))
    );
    assert_eq!(
        e(McsInputs {
            change_decel_jerk: 9,
            ..d
        }),
        Err((13, 6))
    );
    assert_eq!(
        e(McsInputs {
            change_decel_jerk: 1,
            decel_jerk: -1.0,
            ..d
        }),
        Err((13, 7))
    );
    assert_eq!(
        e(McsInputs {
            change_decel_jerk: 1,
            jerk_units: 5,
            ..d
        }),
        Err((13, 8))
    );
    let zero = CoordinateSystem::new(CoordinateSystemConfig {
        max_decel: 0.0,
        ..CoordinateSystemConfig::new("Z")
    })
    .unwrap();
    assert_eq!(Mcs::new(&d, &zero).map_err(|e| (e.err(), e.exerr())), Err((54, -1)));
    let m = Mcs::new(
        &McsInputs {
            change_decel: 1,
            decel_rate: 50.0,
            decel_units: 1,
            ..d
        },
        &sys,
    )
    .unwrap();
    assert_eq!(m.decel, 5.0);
    assert!(m.stop_all);
}
