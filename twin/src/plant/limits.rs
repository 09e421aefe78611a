//! Soft travel limits of the scene's axes.
//!
//! An axis' limits are its `soft_travel_limits = [min, max]` (axis units)
//! when the scene gives them (checked by the scene loader: finite, min < max,
//! not on a modulo axis, the initial position inside). Without that field an
//! axis mapped to a URDF `revolute` or `prismatic` joint takes the joint's
//! `<limit lower upper>`, converted from rad / m to axis units; a `continuous`
//! joint, a virtual axis, a modulo axis (its position wraps) and a `<limit>`
//! with `lower ≥ upper` (a URDF that leaves them out reads as 0, 0) give
//! none, and so does `soft_travel_limit_checking = false`. The run refuses
//! an axis whose initial position is outside its URDF limits, naming the
//! axis' `joint` field.
//!
//! The planner watches the actual position against the limits (a soft
//! overtravel fault with the axis' `soft_overtravel_action`, ERR 9 for a
//! further move out) and keeps what a transform (MCT) commands inside them
//! (see `planner::servo` and `planner::task` module `mct`). A URDF limit is
//! also the joint's physical stop, so an axis driven into it stops there
//! with its actual position just beyond the limit (the stop's compliance):
//! the fault rises as the command pushes on.

use crate::plant::urdf::{JointKind, RobotModel};
use crate::scene::Axis;
use planner::axis::AxisConfig;

/// The planner's configuration of `axis` with its soft travel limits: its
/// own, or else its URDF joint's (module doc).
///
/// # Errors
/// A message (for the axis' `joint` field) when the initial position is
/// outside the URDF limits.
pub fn with_urdf_limits(axis: &Axis, model: &RobotModel) -> Result<AxisConfig, String> {
    let mut config = axis.config.clone();
    if !axis.soft_travel_limit_checking || config.soft_travel_limits.is_some() || config.modulo_period.is_some() {
        return Ok(config);
    }
    let Some(joint) = axis.joint.as_ref().and_then(|name| model.joint_by_name(name)) else {
        return Ok(config);
    };
    let joint = model.joint(joint);
    let Some(limits) = joint
        .limits
        .filter(|_| matches!(joint.kind, JointKind::Revolute | JointKind::Prismatic))
    else {
        return Ok(config);
    };
    if !(limits.lower.is_finite() && limits.upper.is_finite() && limits.lower < limits.upper) {
        return Ok(config);
    }
    let si = axis.units.si_per_unit();
    let (min, max) = (limits.lower / si, limits.upper / si);
    if !(min..=max).contains(&axis.initial_position) {
        return Err(format!(
            "axis '{}' starts at {} {}, outside the <limit lower=\"{}\" upper=\"{}\"> of joint '{}' ([{min}, {max}] {}); \
             move the initial position inside or set soft_travel_limits",
            axis.name, axis.initial_position, axis.units, limits.lower, limits.upper, joint.name, axis.units
        ));
    }
    config.soft_travel_limits = Some((min, max));
    Ok(config)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn scara() -> (crate::scene::Scene, RobotModel) {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let scene = crate::scene::load(&root.join("scara_pick.toml")).expect("scene");
        let model = RobotModel::load(&scene.robot.urdf).expect("urdf");
        (scene, model)
    }

    #[test]
    fn urdf_limits_are_converted_to_axis_units_and_virtual_axes_get_none() {
        let (scene, model) = scara();
        let limits = |name: &str| {
            let axis = scene.axes.iter().find(|a| a.name == name).expect(name);
            with_urdf_limits(axis, &model).expect("inside").soft_travel_limits
        };
        // scara.urdf: j1 ±2.6 rad, j2 ±2.5 rad, j3 [-0.3, 0] m.
        let (min, max) = limits("J1").expect("j1 is revolute");
        assert!((min + 2.6f64.to_degrees()).abs() < 1e-12 && (max - 2.6f64.to_degrees()).abs() < 1e-12);
        assert_eq!(limits("Z"), Some((-0.3, 0.0)));
        assert_eq!(limits("X"), None);
    }

    #[test]
    fn scene_limits_win_and_a_start_outside_the_urdf_limits_is_refused() {
        let (scene, model) = scara();
        let mut axis = scene.axes.iter().find(|a| a.name == "J2").expect("J2").clone();
        axis.config.soft_travel_limits = Some((-10.0, 100.0));
        let config = with_urdf_limits(&axis, &model).expect("inside");
        assert_eq!(config.soft_travel_limits, Some((-10.0, 100.0)));
        axis.config.soft_travel_limits = None;
        axis.initial_position = 150.0;
        assert!(with_urdf_limits(&axis, &model).is_err(), "outside ±143 deg");
        // A modulo axis takes no URDF limits.
        axis.config.modulo_period = Some(360.0);
        let config = with_urdf_limits(&axis, &model).expect("modulo");
        assert_eq!(config.soft_travel_limits, None);
        // Checking off: no limits at all.
        axis.config.modulo_period = None;
        axis.initial_position = 0.0;
        assert!(
            with_urdf_limits(&axis, &model)
                .expect("inside")
                .soft_travel_limits
                .is_some()
        );
        axis.soft_travel_limit_checking = false;
        assert_eq!(with_urdf_limits(&axis, &model).expect("off").soft_travel_limits, None);
    }
}
