//! MAG (Motion Axis Gear): electronic gearing of a slave axis to a master
//! axis at a ratio. The gearing is a process of the engine: its state is
//! an axis' `GearRun` (`task/engine.rs`), and its step each coarse update
//! (`advance_gears`, below) moves the slave.
//!
//! `MAG(SlaveAxis, MasterAxis, MotionControl, Direction, Ratio, SlaveCounts,
//! MasterCounts, MasterReference, RatioFormat, Clutch, AccelRate,
//! AccelUnits)`, as in the Logix motion reference:
//!
//! * **Ratio**: with Ratio Format 0 (*Real*) the slave moves `Ratio` slave
//!   units per master unit; the value is sign sensitive and its magnitude
//!   must lie in 0.00001 ..= 9.99999 (the manual's range), else ERR 13 with
//!   EXERR = the Ratio operand. With Ratio Format 1 (*Fraction*) the ratio
//!   is `SlaveCounts / MasterCounts` (both non-zero integers, else ERR 13
//!   naming the operand). The twin has no encoders: a count is one position
//!   unit of its axis (Logix uses feedback counts, bypassing the conversion
//!   constant; a fraction still gives an exact rational ratio).
//! * **Direction**: 0 *Same* (the ratio as given), 1 *Opposite* (negated),
//!   2 *Reverse* (the opposite of the direction the slave is geared in now;
//!   *Opposite* when it is not geared), 3 *Unchanged* (the current
//!   direction with the new ratio; *Same* when not geared).
//! * **Master Reference**: 0 the master's actual position, 1 its command.
//! * **Clutch**: 0 *enabled*: the slave's gearing velocity ramps from the
//!   slave's current velocity to the geared velocity at `AccelRate`
//!   (trapezoidal), then locks (`GearingLockStatus`); the position offset
//!   built up while clutching is kept, as on a car's clutch. 1 *disabled*:
//!   locked at once (an abrupt start if the master moves, as the manual
//!   warns). `AccelRate` in units/s² (AccelUnits 0) or % of the slave's
//!   maximum acceleration (1); it must be > 0 with the clutch enabled.
//! * The configured velocity and acceleration limits do not apply to
//!   gearing (the manual says so).
//!
//! Bits: `.DN` when gearing is initiated, `.IP` until it is superseded by
//! another MAG on the slave, stopped (MAS *All* or *Gear*), ended by a MAM
//! that merges or a MAJ, by a move, coordinated motion or a position cam
//! taking the slave, or by a disable (MSF, shutdown, a fault). A MAM with
//! Merge Disabled runs superimposed on the gearing, as on a cam. The slave
//! needs the servo on (ERR 5/7/8/16/53 as every move); the master may be in
//! any state. A slave that is its own master is refused with ERR 13 naming
//! the Master Axis operand.

use crate::axis::AxisConfig;
use crate::catalogue::Word;
use crate::catalogue::words::{motion_control, ACTUAL_COMMAND, JOG_ACCEL_UNITS, MAPC_DIRECTION, op, w};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, one_shot, no_load};
use crate::dynamics::time_rate;
use crate::instruction::{NoFault, Refusal};
use crate::mapc::MasterReference;
use crate::profile::Sample;
use crate::task::engine::GearRun;
use crate::task::engine::Need;
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};

/// Ratio Format's words (MAG's own).
pub const RATIO_FORMAT: &[Word] = &[w("real", 0), w("fraction_slave_master_counts", 1)];
/// Clutch's words (MAG's own).
pub const CLUTCH: &[Word] = &[w("enabled", 0), w("disabled", 1)];

/// Motion Axis Gear.
pub const MAG: Instruction = Instruction {
    mnemonic: "MAG",
    title: "Motion Axis Gear",
    summary: "electronic gearing: real or fractional ratio, direction (same, opposite, reverse, unchanged), master actual or command, clutch; a MAM with Merge Disabled rides on it; MAS Gear or All stops it",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Slave Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        op("Master Axis", "AXIS", Format::Tag, Kind::Axis, 1),
        motion_control(2),
        op("Direction", "DINT", Format::Immediate, Kind::Enumeration(MAPC_DIRECTION), 3),
        op("Ratio", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
        op("Slave Counts", "DINT", Format::ImmediateOrTag, Kind::Integer, 5),
        op("Master Counts", "DINT", Format::ImmediateOrTag, Kind::Integer, 6),
        op(
            "Master Reference",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            7,
        ),
        op("Ratio Format", "DINT", Format::Immediate, Kind::Enumeration(RATIO_FORMAT), 8),
        op("Clutch", "DINT", Format::Immediate, Kind::Enumeration(CLUTCH), 9),
        op("Accel Rate", "REAL", Format::ImmediateOrTag, Kind::Number, 10),
        op("Accel Units", "DINT", Format::Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 11),
    ],
    execute,
    check,
    load: no_load,
};

/// MAG's numeric operands (enumerations as their codes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagOperands {
    /// 0 Same, 1 Opposite, 2 Reverse, 3 Unchanged.
    pub direction: i32,
    /// Real ratio (Ratio Format 0).
    pub ratio: f64,
    /// Slave counts (Ratio Format 1).
    pub slave_counts: i32,
    /// Master counts (Ratio Format 1).
    pub master_counts: i32,
    /// 0 actual, 1 command.
    pub master_reference: i32,
    /// 0 real, 1 fraction.
    pub ratio_format: i32,
    /// 0 enabled, 1 disabled.
    pub clutch: i32,
    /// Clutch acceleration.
    pub accel_rate: f64,
    /// 0 units/s², 1 % of maximum.
    pub accel_units: i32,
}

impl Default for MagOperands {
    fn default() -> Self {
        Self {
            direction: 0,
            ratio: 1.0,
            slave_counts: 1,
            master_counts: 1,
            master_reference: 0,
            ratio_format: 0,
            clutch: 1,
            accel_rate: 100.0,
            accel_units: 1,
        }
    }
}

/// Why MAG fails: ERR 13 with the operand, or the slave's state.
pub type MagError = Refusal<NoFault>;

impl MagOperands {
    /// The operands of a call, by catalogue position.
    ///
    /// # Errors
    /// ERR 13 for Slave Counts or Master Counts beyond a DINT.
    pub fn bind(args: &Args<'_>) -> Result<Self, MagError> {
        let dint = |i: usize| {
            let n = args.integer(i);
            i32::try_from(n).map_err(|_| Refusal::operand(MAG.operands[i].faceplate, n as f64))
        };
        Ok(MagOperands {
            direction: args.code(3),
            ratio: args.number(4),
            slave_counts: dint(5)?,
            master_counts: dint(6)?,
            master_reference: args.code(7),
            ratio_format: args.code(8),
            clutch: args.code(9),
            accel_rate: args.number(10),
            accel_units: args.code(11),
        })
    }
}

/// MAG's Direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GearDirection {
    /// 0.
    Same,
    /// 1.
    Opposite,
    /// 2.
    Reverse,
    /// 3.
    Unchanged,
}

/// A validated MAG.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mag {
    /// Direction.
    pub direction: GearDirection,
    /// Slave units per master unit, as given (sign included).
    pub ratio: f64,
    /// Which master position drives the slave.
    pub master_reference: MasterReference,
    /// Clutch acceleration, units/s² (`None`: clutch disabled).
    pub clutch_accel: Option<f64>,
}

/// The smallest and largest |Ratio| of the real format.
pub const RATIO_RANGE: (f64, f64) = (0.00001, 9.99999);

impl Mag {
    /// Validates the operands against the slave's configuration.
    ///
    /// # Errors
    /// ERR 13 ([`Refusal::Operand`]) naming the first operand at fault.
    pub fn new(o: &MagOperands, slave: &AxisConfig) -> Result<Self, MagError> {
        let bad = |name: &str, value: f64| Refusal::operand(MAG.exerr(name), value);
        let direction = match o.direction {
            0 => GearDirection::Same,
            1 => GearDirection::Opposite,
            2 => GearDirection::Reverse,
            3 => GearDirection::Unchanged,
            d => return Err(bad("Direction", f64::from(d))),
        };
        let ratio = match o.ratio_format {
            0 => {
                let m = o.ratio.abs();
                if !(o.ratio.is_finite() && (RATIO_RANGE.0..=RATIO_RANGE.1).contains(&m)) {
                    return Err(bad("Ratio", o.ratio));
                }
                o.ratio
            }
            1 => {
                if o.slave_counts == 0 {
                    return Err(bad("Slave Counts", 0.0));
                }
                if o.master_counts == 0 {
                    return Err(bad("Master Counts", 0.0));
                }
                f64::from(o.slave_counts) / f64::from(o.master_counts)
            }
            f => return Err(bad("Ratio Format", f64::from(f))),
        };
        let master_reference = match o.master_reference {
            0 => MasterReference::Actual,
            1 => MasterReference::Command,
            r => return Err(bad("Master Reference", f64::from(r))),
        };
        let clutch_accel = match o.clutch {
            0 => {
                let Some(a) = time_rate(o.accel_rate, i64::from(o.accel_units), slave.max_acceleration) else {
                    return Err(bad("Accel Units", f64::from(o.accel_units)));
                };
                if !(a.is_finite() && a > 0.0) {
                    return Err(bad("Accel Rate", o.accel_rate));
                }
                Some(a)
            }
            1 => None,
            c => return Err(bad("Clutch", f64::from(c))),
        };
        Ok(Self {
            direction,
            ratio,
            master_reference,
            clutch_accel,
        })
    }

    /// The signed ratio the slave follows, given the sign of the gearing
    /// running now (`None`: not geared).
    pub fn effective_ratio(&self, current_sign: Option<f64>) -> f64 {
        let sign = match self.direction {
            GearDirection::Same => 1.0,
            GearDirection::Opposite => -1.0,
            GearDirection::Reverse => -current_sign.unwrap_or(1.0),
            GearDirection::Unchanged => current_sign.unwrap_or(1.0),
        };
        sign * self.ratio
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    one_shot(task, control, |task| MagOperands::bind(args).and_then(|o| task.mag(args.axis(0), args.axis(1), control, &o)))
}

fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let o = MagOperands::bind(args).map_err(fault)?;
    Mag::new(&o, task.axis_config(args.axis(0))).map_err(fault)?;
    same_axes(args.axis(0), args.axis(1)).map_err(fault)
}

/// An axis geared to itself: ERR 13 on the Master Axis.
fn same_axes(slave: AxisHandle, master: AxisHandle) -> Result<(), MagError> {
    if slave == master {
        return Err(Refusal::Operand {
            exerr: MAG.exerr("Master Axis"),
            value: None,
        });
    }
    Ok(())
}

impl MotionTask {
    /// MAG: gears `slave` to `master` at the operands' ratio (see the
    /// module doc). A MAG on a slave already geared supersedes the
    /// running one (its `.IP` clears); the clutch then starts from the
    /// gearing velocity it had.
    ///
    /// # Errors
    /// ERR 13 (EXERR = the operand), or the slave's state error (5, 7, 8,
    /// 16, 53).
    pub(crate) fn mag(
        &mut self,
        slave: AxisHandle,
        master: AxisHandle,
        control: InstructionHandle,
        operands: &MagOperands,
    ) -> Result<(), MagError> {
        let mag = self.instruction(control, |task| {
            let m = Mag::new(operands, &task.axes[slave.0 as usize].config)?;
            same_axes(slave, master)?;
            task.check_state(slave, Need::Motion)?;
            // The master decides the direction: either side counts.
            task.check_overtravel(slave, 0.0)?;
            Ok::<_, MagError>(m)
        })?;
        let previous = self.axes[slave.0 as usize].gear.take();
        let current_sign = previous.as_ref().map(|g| g.ratio.signum());
        let velocity = match &previous {
            Some(g) => {
                self.motion_bits_mut(g.control).ip = false;
                g.velocity
            }
            None => {
                let a = &self.axes[slave.0 as usize];
                let sup = self.superimposed(slave).map_or(0.0, |s| s.velocity);
                a.command.velocity - sup
            }
        };
        // The gearing takes the slave from a move or a cam; a jog or MAM
        // running on it goes on superimposed.
        self.abort_move(slave);
        self.end_cams(slave);
        self.superimpose_running_ramp(slave);
        let key = (master, mag.master_reference);
        self.axes[slave.0 as usize].gear = Some(GearRun {
            control,
            master,
            reference: mag.master_reference,
            ratio: mag.effective_ratio(current_sign),
            last_master: self.cam_master_position(key),
            clutch: mag.clutch_accel,
            velocity,
        });
        let b = self.motion_bits_mut(control);
        b.dn = true;
        b.ip = true;
        Ok(())
    }
}

// The gearing process. Each coarse update, after jogs, moves and cams
// have advanced, a geared slave's command moves by `ratio × Δmaster` (the
// master's actual or command position, its MRP redefinitions taken out, as
// for a cam); while the clutch is slipping, by the clutch velocity instead,
// which ramps to `ratio × master velocity` at the clutch acceleration and
// then locks.
impl MotionTask {
    /// Whether `axis` is geared (`GearingStatus`), and locked to its master
    /// (`GearingLockStatus`: not while the clutch slips).
    pub fn gearing_status(&self, axis: AxisHandle) -> (bool, bool) {
        match &self.axes[axis.0 as usize].gear {
            Some(g) => (true, g.clutch.is_none()),
            None => (false, false),
        }
    }

    /// Ends the gearing of `axis` (`.IP` clears; the command keeps its
    /// state for whatever takes the axis next).
    pub(crate) fn end_gear(&mut self, axis: AxisHandle) -> bool {
        match self.axes[axis.0 as usize].gear.take() {
            Some(g) => {
                self.motion_bits_mut(g.control).ip = false;
                true
            }
            None => false,
        }
    }

    /// Step of an update: every geared slave follows its master.
    pub(crate) fn advance_gears(&mut self) {
        let dt = self.dt_s;
        for i in 0..self.axes.len() {
            let Some(mut g) = self.axes[i].gear.take() else {
                continue;
            };
            let m = self.cam_master_position((g.master, g.reference));
            let dm = m - g.last_master;
            g.last_master = m;
            let geared_velocity = g.ratio * dm / dt;
            let dp = match g.clutch {
                None => g.ratio * dm,
                Some(accel) => {
                    let step = accel * dt;
                    let dv = geared_velocity - g.velocity;
                    if dv.abs() <= step {
                        g.clutch = None;
                        g.ratio * dm
                    } else {
                        g.velocity += step.copysign(dv);
                        g.velocity * dt
                    }
                }
            };
            let old = self.axes[i].command;
            let v = dp / dt;
            if g.clutch.is_none() {
                g.velocity = v;
            }
            self.axes[i].gear = Some(g);
            self.set_command(
                AxisHandle(i as u32),
                Sample {
                    position: old.position + dp,
                    velocity: v,
                    acceleration: (v - old.velocity) / dt,
                    jerk: 0.0,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests;
