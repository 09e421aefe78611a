//! Places: reading and writing tag memory, bits, and the members the
//! planner keeps.

use super::Exec;
use crate::program::ir::{AxisMember, CExpr, CoordMember, FbMember, MotionMember, Place};
use crate::program::types::{DataType, Value};
use planner::instruction::MotionInstructionBits;
use planner::task::{AxisHandle, MotionTask};

impl Exec<'_> {
    /// The slot a place reads or writes (`None` for the planner's places,
    /// or when its subscript is out of range, which records the fault).
    pub(super) fn slot(&mut self, place: &Place) -> Option<usize> {
        match place {
            Place::Slot(i) => Some(*i),
            Place::Element { len, index, name, .. } => {
                let i = self.leaf(index).as_i64();
                let slot = place.element_slot(i);
                if slot.is_none() {
                    let f = self.subscript_fault(name, i, *len);
                    self.fail(f);
                }
                slot
            }
            _ => None,
        }
    }

    pub(super) fn bit_number(&mut self, bit: &CExpr, width: u32) -> Option<u32> {
        let b = self.leaf(bit).as_i64();
        if b < 0 || b >= i64::from(width) {
            let f = self.raise(4, 20, format!("bit {b} is outside a {width}-bit integer"));
            self.fail(f);
            return None;
        }
        Some(b as u32)
    }

    /// Reads a place (0 after a subscript fault, which is recorded).
    pub fn load(&mut self, place: &Place) -> Value {
        if let Place::Slot(i) = place {
            return self.mem.slots[*i];
        }
        if let Place::Element { .. } = place {
            return self.slot(place).map_or(Value::Int(0), |i| self.mem.slots[i]);
        }
        match place {
            Place::Bit { inner, width, bit, .. } => {
                let v = self.load(inner).as_i64();
                let b = self.bit_number(bit, *width).unwrap_or(0);
                Value::Bool(v >> b & 1 == 1)
            }
            Place::Motion(..) | Place::Axis(..) | Place::Coord(..) | Place::Fb(..) => {
                planner_value(place, self.task).unwrap_or(Value::Int(0))
            }
            Place::FirstScan => Value::Bool(self.first_scan),
            Place::MinorInScan => Value::Bool(!self.minor.is_empty()),
            Place::MinorFaults => Value::Int(self.minor_total.min(i64::from(i32::MAX))),
            Place::Slot(_) | Place::Element { .. } => unreachable!("slots read above"),
        }
    }

    /// Writes a place, converting to its type; nothing after a fault of the
    /// statement (a subscript out of range is recorded).
    pub fn store(&mut self, place: &Place, ty: DataType, v: Value) {
        if self.fault.is_some() {
            return;
        }
        // The common case, a DINT value into a DINT, needs no conversion.
        let (stored, bad) = match (ty, v) {
            (DataType::Dint, Value::Int(x)) if i32::try_from(x).is_ok() => (v, false),
            _ => ty.store(v),
        };
        if bad {
            self.overflow(&format!("the value does not fit {}", ty.name()));
        }
        if let Place::Slot(i) = place {
            self.mem.slots[*i] = stored;
            return;
        }
        if let Place::Element { .. } = place {
            if let Some(i) = self.slot(place) {
                self.mem.slots[i] = stored;
            }
            return;
        }
        match place {
            Place::Bit { inner, width, bit, ty } => {
                let Some(b) = self.bit_number(bit, *width) else { return };
                let old = self.load(inner).as_i64();
                let new = if stored.truthy() { old | 1 << b } else { old & !(1 << b) };
                let (value, _) = ty.store(Value::Int(ty.wrap(i128::from(new))));
                self.store(inner, *ty, value);
            }
            Place::Motion(h, MotionMember::Bit(name)) => {
                let mut bits = self.task.motion_bits(*h);
                set_bit(&mut bits, name, stored.truthy());
                self.task.set_motion_bits(*h, bits);
            }
            _ => unreachable!("the compiler refuses writes to read-only places"),
        }
    }
}

/// Sets a `MOTION_INSTRUCTION` bit by its name.
fn set_bit(bits: &mut MotionInstructionBits, name: &str, v: bool) {
    match name {
        "EN" => bits.en = v,
        "DN" => bits.dn = v,
        "ER" => bits.er = v,
        "IP" => bits.ip = v,
        "AC" => bits.ac = v,
        "PC" => bits.pc = v,
        "ACCEL" => bits.accel = v,
        _ => bits.decel = v,
    }
}

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
    }
}
