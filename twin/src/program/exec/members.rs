//! The members the planner keeps — a control structure's bits and codes,
//! an axis', a coordinate system's, a function block's outputs — as values
//! a program reads.

use crate::program::ir::{AxisMember, CoordMember, FbMember, GroupMember, GroupWord, MotionMember, Place};
use crate::program::types::Value;
use planner::task::{AxisHandle, MotionTask};

/// The value of a member the planner keeps (a control structure's, an
/// axis', a coordinate system's, a function block's), as a program reads
/// it; `None` for places in tag memory.
pub(in crate::program) fn planner_value(place: &Place, task: &MotionTask) -> Option<Value> {
    Some(match place {
        Place::Motion(h, member) => {
            let bits = task.motion_bits(*h);
            match member {
                MotionMember::Bit(name) => Value::Bool(bits.bit(name).unwrap_or(false)),
                MotionMember::Err => Value::Int(i64::from(bits.err)),
                MotionMember::Exerr => Value::Int(i64::from(bits.exerr)),
                MotionMember::Segment => Value::Int(i64::from(bits.segment)),
            }
        }
        Place::Axis(h, m) => axis_value(task, *h, *m),
        Place::Coord(h, m) => Value::Bool(match m {
            CoordMember::Status(name) => task.coord_status(*h).bits().into_iter().any(|(n, b)| n == *name && b),
            CoordMember::TransformSource => task.transform_source_status(*h),
            CoordMember::TransformTarget => task.transform_target_status(*h),
        }),
        Place::Group(m) => {
            let s = task.group_status();
            match m {
                GroupMember::Word(w) => Value::Int(i64::from(match w {
                    GroupWord::GroupStatus => s.group_status,
                    GroupWord::MotionFault => s.motion_fault,
                    GroupWord::ServoFault => s.servo_fault,
                    GroupWord::GroupFault => s.group_fault,
                    GroupWord::AxisFault => s.axis_fault,
                })),
                GroupMember::StatusBit(bit) => Value::Bool(s.group_status >> bit & 1 == 1),
            }
        }
        Place::Fb(h, m) => {
            let o = task.outputs(*h);
            match m {
                FbMember::Bit(name) => Value::Bool(o.bits().into_iter().any(|(n, b)| n == *name && b)),
                FbMember::ErrorId => Value::Int(i64::from(o.error_id)),
            }
        }
        _ => return None,
    })
}

/// An axis member: positions and velocities at REAL precision.
pub(in crate::program) fn axis_value(task: &MotionTask, h: AxisHandle, m: AxisMember) -> Value {
    let s = task.axis_state(h);
    let real = |x: f64| Value::Real(f64::from(x as f32));
    match m {
        AxisMember::ActualPosition => real(s.actual_position),
        AxisMember::CommandPosition => real(s.command_position),
        AxisMember::ActualVelocity => real(s.actual_velocity),
        AxisMember::CommandVelocity => real(s.command_velocity),
        AxisMember::CommandAcceleration => real(s.command_acceleration),
        AxisMember::CoordinatedMotionStatus => Value::Bool(task.coordinated_motion_status(h)),
        AxisMember::PositionCamStatus => Value::Bool(task.slave_cam_status(h).position_cam),
        AxisMember::PositionCamLockStatus => Value::Bool(task.slave_cam_status(h).lock),
        AxisMember::PositionCamPendingStatus => Value::Bool(task.slave_cam_status(h).pending),
        AxisMember::TransformStateStatus => Value::Bool(task.transform_state_status(h)),
        AxisMember::ControlledByTransformStatus => Value::Bool(task.controlled_by_transform_status(h)),
        AxisMember::CipAxisState => Value::Int(i64::from(task.cip_axis_state(h).code())),
        AxisMember::AxisFault => Value::Int(i64::from(task.axis_faults(h).0)),
        AxisMember::ServoActionStatus => Value::Bool(task.axis_status(h).servo_action),
        AxisMember::DriveEnableStatus => Value::Bool(task.axis_status(h).drive_enable),
        AxisMember::ShutdownStatus => Value::Bool(task.axis_status(h).shutdown),
        AxisMember::InhibitStatus => Value::Bool(task.axis_status(h).inhibit),
        AxisMember::AxisHomedStatus => Value::Bool(task.axis_status(h).homed),
        AxisMember::HomingStatus => Value::Bool(task.axis_status(h).homing),
        AxisMember::MoveStatus => Value::Bool(task.axis_status(h).moving),
        AxisMember::JogStatus => Value::Bool(task.axis_status(h).jogging),
        AxisMember::GearingStatus => Value::Bool(task.axis_status(h).gearing),
        AxisMember::GearingLockStatus => Value::Bool(task.gearing_status(h).1),
        AxisMember::StoppingStatus => Value::Bool(task.axis_status(h).stopping),
        AxisMember::MotionFault => Value::Int(i64::from(task.motion_faults(h).0)),
        AxisMember::SoftTravelLimitPositiveFault => Value::Bool(task.motion_faults(h).positive()),
        AxisMember::SoftTravelLimitNegativeFault => Value::Bool(task.motion_faults(h).negative()),
        AxisMember::SoftTravelLimitChecking => Value::Bool(task.axis_config(h).soft_travel_limits.is_some()),
        AxisMember::SoftTravelLimitPositive => real(task.axis_config(h).soft_travel_limits.map_or(0.0, |l| l.1)),
        AxisMember::SoftTravelLimitNegative => real(task.axis_config(h).soft_travel_limits.map_or(0.0, |l| l.0)),
        AxisMember::RegistrationPosition(n) => real(task.registration(h, n).map_or(0.0, |r| r.position)),
        AxisMember::RegEventStatus(n) => Value::Bool(task.registration(h, n).is_some_and(|r| r.event)),
        AxisMember::RegEventArmedStatus(n) => Value::Bool(task.registration(h, n).is_some_and(|r| r.armed())),
        AxisMember::TimeCamStatus => Value::Bool(task.time_cam_status(h).0),
        AxisMember::TimeCamPendingStatus => Value::Bool(task.time_cam_status(h).1),
        AxisMember::WatchEventArmedStatus => Value::Bool(task.watch(h).armed()),
        AxisMember::WatchEventStatus => Value::Bool(task.watch(h).event),
        AxisMember::WatchPosition => real(task.watch(h).position),
        AxisMember::StrobeActualPosition => real(task.strobe_positions(h).0),
        AxisMember::StrobeCommandPosition => real(task.strobe_positions(h).1),
    }
}
