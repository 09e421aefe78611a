//! MCCP, MAPC, MRP, MAJ and MAS through the motion task: slave positions and
//! every status bit over time, the spec's tables and figure sequences, and
//! every error code.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::mapc::MapcOperands;
use crate::mapc::axis::SlaveCamStatus;
use crate::mccp::CamElement;
use crate::modulo::{McBufferMode, McDirection, MoveModuloInputs};

const DT: f64 = 0.01;

fn axis(name: &str) -> AxisConfig {
    AxisConfig {
        max_velocity: 1000.0,
        max_acceleration: 10000.0,
        max_deceleration: 10000.0,
        ..AxisConfig::new(name, AxisKind::Linear)
    }
}

struct Rig {
    task: MotionTask,
    master: AxisHandle,
    slave: AxisHandle,
}

fn rig() -> Rig {
    let mut task = MotionTask::new(DT).unwrap();
    let master = task.add_axis(axis("Conveyor"), 0.0).unwrap();
    let slave = task.add_axis(axis("Knife"), 0.0).unwrap();
    Rig { task, master, slave }
}

impl Rig {
    /// A profile through `points`, all segments of `segment_type`.
    fn profile(&mut self, name: &str, points: &[(f64, f64)], segment_type: i32) -> CamProfileHandle {
        let cam: Vec<CamElement> = points
            .iter()
            .map(|&(master, slave)| CamElement {
                master,
                slave,
                segment_type,
            })
            .collect();
        let h = self.task.add_cam_profile(name, 32);
        let mi = self.task.add_instruction(format!("MCCP_{name}"));
        self.task.mccp(mi, &cam, cam.len(), 0.0, 0.0, h).unwrap();
        assert!(self.task.motion_bits(mi).dn);
        h
    }

    fn mapc(
        &mut self,
        mi: InstructionHandle,
        profile: CamProfileHandle,
        operands: MapcOperands,
    ) -> Result<(), MapcError> {
        self.task.mapc(MapcCall {
            slave: self.slave,
            master: self.master,
            motion_control: mi,
            cam_profile: profile,
            operands,
        })
    }

    /// The master's device reports `m` (its own frame: the rig adds the
    /// axis' MRP offset, as the twin's plant does), then one coarse update.
    fn to(&mut self, m: f64) {
        let offset = self.task.position_offset(self.master);
        self.task.feed_actual_position(self.master, m + offset);
        self.task.update();
    }

    fn slave_pos(&self) -> f64 {
        self.task.axis_state(self.slave).command_position
    }

    fn status(&self) -> SlaveCamStatus {
        self.task.slave_cam_status(self.slave)
    }

    /// Asserts exactly the named bits (of EN DN ER IP AC PC) are set.
    #[track_caller]
    fn bits(&self, mi: InstructionHandle, set: &str) {
        let b = self.task.motion_bits(mi);
        let actual: Vec<&str> = [
            ("EN", b.en),
            ("DN", b.dn),
            ("ER", b.er),
            ("IP", b.ip),
            ("AC", b.ac),
            ("PC", b.pc),
        ]
        .iter()
        .filter(|(_, v)| *v)
        .map(|(n, _)| *n)
        .collect();
        assert_eq!(actual.join(" "), set, "bits of {}", self.task.instruction_name(mi));
    }

    /// Asserts exactly the named slave status bits (cam lock pending) are set.
    #[track_caller]
    fn slave_bits(&self, set: &str) {
        let s = self.status();
        let actual: Vec<&str> = [("cam", s.position_cam), ("lock", s.lock), ("pending", s.pending)]
            .iter()
            .filter(|(_, v)| *v)
            .map(|(n, _)| *n)
            .collect();
        assert_eq!(actual.join(" "), set, "slave status");
    }

    #[track_caller]
    fn slave_at(&self, expected: f64) {
        let s = self.slave_pos();
        assert!((s - expected).abs() < 1e-9, "slave {s}, expected {expected}");
    }
}

fn ops(mode: i32, schedule: i32) -> MapcOperands {
    MapcOperands {
        execution_mode: mode,
        execution_schedule: schedule,
        ..MapcOperands::default()
    }
}

const ONCE: i32 = 0;
const CONTINUOUS: i32 = 1;
const PERSISTENT: i32 = 2;
const IMMEDIATE: i32 = 0;
const PENDING: i32 = 1;
const FORWARD: i32 = 2;
const REVERSE: i32 = 3;
const BIDIRECTIONAL: i32 = 4;

/// The spec's cam figure: master 0/10/20/30/40, slave 0/30/35/30/0.
const TABLE: [(f64, f64); 5] = [(0.0, 0.0), (10.0, 30.0), (20.0, 35.0), (30.0, 30.0), (40.0, 0.0)];

#[test]
fn cam_lock_position_table_value_for_value() {
    // Cam Lock Position 0: the slave follows the table.
    let mut r = rig();
    let p = r.profile("Cam", &TABLE, 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(mi, p, ops(ONCE, IMMEDIATE)).unwrap();
    for (m, s) in TABLE {
        r.to(m);
        r.slave_at(s);
    }
    // Cam Lock Position 10: each row shifted by the slave at 10 (30):
    // 1' = 30 − 30 = 0, 2' = 35 − 30 = 5, 3' = 30 − 30 = 0, 4' = 0 − 30 = −30
    // (the spec prints "= 30" for the last row: a sign typo).
    let mut r = rig();
    let p = r.profile("Cam", &TABLE, 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.to(10.0);
    r.mapc(
        mi,
        p,
        MapcOperands {
            cam_lock_position: 10.0,
            ..ops(ONCE, IMMEDIATE)
        },
    )
    .unwrap();
    let shifted = [(10.0, 0.0), (20.0, 5.0), (30.0, 0.0), (40.0, -30.0)];
    for (i, (m, s)) in shifted.into_iter().enumerate() {
        r.to(m);
        assert_eq!(s, TABLE[i + 1].1 - 30.0);
        r.slave_at(s);
    }
    // "Profile ended": the End of Cam Boundary.
    r.bits(mi, "EN DN IP AC");
    r.to(41.0);
    r.bits(mi, "EN DN PC");
    r.slave_at(-30.0);
}

#[test]
fn once_completes_at_the_boundary_and_never_resumes() {
    let mut r = rig();
    let p = r.profile("Cam", &TABLE, 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(mi, p, ops(ONCE, IMMEDIATE)).unwrap();
    r.bits(mi, "EN DN IP AC");
    r.slave_bits("cam lock");
    assert_eq!(r.task.cam_profile(p).status(), 3);
    r.to(5.0);
    r.slave_at(15.0);
    r.to(45.0);
    r.slave_at(0.0);
    r.bits(mi, "EN DN PC");
    r.slave_bits("");
    assert_eq!(r.task.cam_profile(p).status(), 2);
    r.to(10.0);
    r.slave_at(0.0);
    assert_eq!(r.task.axis_state(r.slave).command_velocity, 0.0);
    r.task.rung_false(mi);
    r.bits(mi, "DN PC");
}

#[test]
fn continuous_repeats_the_profile_both_ways() {
    let mut r = rig();
    // Net rise 10 per cycle of 20.
    let p = r.profile("Ramp", &[(0.0, 0.0), (10.0, 8.0), (20.0, 10.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(mi, p, ops(CONTINUOUS, IMMEDIATE)).unwrap();
    for (m, s) in [
        (10.0, 8.0),
        (20.0, 10.0),
        (30.0, 18.0),
        (50.0, 28.0),
        (-5.0, -1.0),
        (-15.0, -6.0),
    ] {
        r.to(m);
        r.slave_at(s);
        r.bits(mi, "EN DN IP AC");
        r.slave_bits("cam lock");
    }
}

#[test]
fn persistent_holds_outside_and_resumes_inside() {
    let mut r = rig();
    let p = r.profile("Cam", &TABLE, 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(mi, p, ops(PERSISTENT, IMMEDIATE)).unwrap();
    r.to(40.0);
    r.slave_at(0.0);
    r.slave_bits("cam lock");
    r.to(50.0);
    r.slave_at(0.0);
    r.slave_bits("cam");
    r.bits(mi, "EN DN IP AC");
    r.to(20.0);
    r.slave_at(35.0);
    r.slave_bits("cam lock");
    r.to(-3.0);
    r.slave_at(0.0);
    r.slave_bits("cam");
    r.bits(mi, "EN DN IP AC");
}

#[test]
fn forward_only_schedule_locks_at_the_master_lock_position() {
    let mut r = rig();
    let p = r.profile("Slope3", &[(0.0, 0.0), (100.0, 300.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.to(0.0);
    r.mapc(
        mi,
        p,
        MapcOperands {
            master_lock_position: 5.0,
            ..ops(ONCE, FORWARD)
        },
    )
    .unwrap();
    r.bits(mi, "EN DN IP");
    r.slave_bits("cam");
    r.to(3.0);
    r.slave_at(0.0);
    r.bits(mi, "EN DN IP");
    r.to(8.0);
    r.slave_at(9.0);
    r.bits(mi, "EN DN IP AC");
    r.slave_bits("cam lock");
}

#[test]
fn reverse_only_schedule_ignores_forward_crossings() {
    let mut r = rig();
    let p = r.profile("Slope3", &[(0.0, 0.0), (100.0, 300.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(
        mi,
        p,
        MapcOperands {
            master_lock_position: 5.0,
            cam_lock_position: 50.0,
            ..ops(ONCE, REVERSE)
        },
    )
    .unwrap();
    r.to(10.0);
    r.slave_at(0.0);
    r.bits(mi, "EN DN IP");
    r.to(4.0);
    // Locked at 5 at cam position 50, one unit back: 3 × (49 − 50).
    r.slave_at(-3.0);
    r.bits(mi, "EN DN IP AC");
}

#[test]
fn bidirectional_schedule_locks_either_way() {
    for (start, end, expected) in [(0.0, 7.0, 6.0), (10.0, 4.0, -3.0)] {
        let mut r = rig();
        let p = r.profile("Slope3", &[(0.0, 0.0), (100.0, 300.0)], 0);
        let mi = r.task.add_instruction("MAPC_1");
        r.to(start);
        r.mapc(
            mi,
            p,
            MapcOperands {
                master_lock_position: 5.0,
                cam_lock_position: 50.0,
                ..ops(ONCE, BIDIRECTIONAL)
            },
        )
        .unwrap();
        r.to(start);
        r.slave_at(0.0);
        r.to(end);
        r.slave_at(expected);
        r.bits(mi, "EN DN IP AC");
    }
}

#[test]
fn master_offset_shifts_the_lock_position() {
    // Master Lock 50, master offset 10: the slave locks at master 40.
    let mut r = rig();
    let p = r.profile("Slope3", &[(0.0, 0.0), (100.0, 300.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.task.shift_master_offset(r.slave, 25.0);
    r.mapc(
        mi,
        p,
        MapcOperands {
            master_lock_position: 50.0,
            ..ops(ONCE, FORWARD)
        },
    )
    .unwrap();
    // The MAPC reset the earlier offset; a master offset move after it counts.
    assert_eq!(r.task.cam.axes[r.slave.0 as usize].cam.master_offset(), 0.0);
    r.task.shift_master_offset(r.slave, 10.0);
    r.to(39.0);
    r.slave_at(0.0);
    r.bits(mi, "EN DN IP");
    r.to(41.0);
    r.slave_at(3.0);
    r.bits(mi, "EN DN IP AC");
}

#[test]
fn pending_cam_takes_over_at_the_end_of_the_active_cam() {
    let mut r = rig();
    let a = r.profile("Accel", &[(0.0, 0.0), (10.0, 10.0)], 0);
    let b = r.profile("Run", &[(0.0, 0.0), (10.0, 20.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    r.mapc(ma, a, ops(ONCE, IMMEDIATE)).unwrap();
    r.mapc(mb, b, ops(CONTINUOUS, PENDING)).unwrap();
    r.bits(mb, "EN DN IP");
    r.slave_bits("cam lock pending");
    r.to(8.0);
    r.slave_at(8.0);
    // The boundary is crossed at 10; B runs from there: 10 + 2 × 5.
    r.to(15.0);
    r.slave_at(20.0);
    r.bits(ma, "EN DN PC");
    r.bits(mb, "EN DN IP AC");
    r.slave_bits("cam lock");
    assert_eq!(r.task.cam_profile(a).status(), 2);
    assert_eq!(r.task.cam_profile(b).status(), 3);
    r.to(35.0);
    r.slave_at(60.0);
}

#[test]
fn pending_cam_can_be_preloaded_before_the_first_cam() {
    let mut r = rig();
    let a = r.profile("Accel", &[(0.0, 0.0), (10.0, 10.0)], 0);
    let b = r.profile("Run", &[(0.0, 0.0), (10.0, 20.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    r.mapc(mb, b, ops(ONCE, PENDING)).unwrap();
    r.bits(mb, "EN DN IP");
    r.slave_bits("pending");
    r.to(5.0);
    r.slave_at(0.0);
    r.to(0.0);
    r.mapc(ma, a, ops(ONCE, IMMEDIATE)).unwrap();
    r.slave_bits("cam lock pending");
    r.to(12.0);
    r.slave_at(14.0);
    r.bits(ma, "EN DN PC");
    r.bits(mb, "EN DN IP AC");
    r.to(25.0);
    r.bits(mb, "EN DN PC");
    r.slave_at(30.0);
    r.slave_bits("");
}

#[test]
fn continuous_cam_hands_over_to_a_pending_cam_at_the_end_of_its_cycle() {
    let mut r = rig();
    let a = r.profile("Run", &[(0.0, 0.0), (10.0, 10.0)], 0);
    let b = r.profile("Decel", &[(0.0, 0.0), (10.0, 5.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    r.mapc(ma, a, ops(CONTINUOUS, IMMEDIATE)).unwrap();
    r.to(13.0);
    r.slave_at(13.0);
    r.mapc(mb, b, ops(ONCE, PENDING)).unwrap();
    r.to(18.0);
    r.slave_at(18.0);
    // End of the second cycle at 20, then B: 20 + 0.5 × 4.
    r.to(24.0);
    r.slave_at(22.0);
    r.bits(ma, "EN DN");
    r.bits(mb, "EN DN IP AC");
}

#[test]
fn replacement_cam_cancels_a_pending_cam() {
    // The spec's "Pending Cam status flags" figure: (1) active cam starts,
    // (2) pending cam enabled (.IP .DN), (3) a replacement executes before the
    // active cam ends (the pending .IP resets), (4) the replacement completes
    // (.PC).
    let mut r = rig();
    let a = r.profile("A", &[(0.0, 0.0), (20.0, 20.0)], 0);
    let b = r.profile("B", &[(0.0, 0.0), (20.0, 40.0)], 0);
    let c = r.profile("C", &[(0.0, 0.0), (10.0, 5.0)], 0);
    let (ma, mb, mc) = (
        r.task.add_instruction("MAPC_A"),
        r.task.add_instruction("MAPC_B"),
        r.task.add_instruction("MAPC_C"),
    );
    r.mapc(ma, a, ops(ONCE, IMMEDIATE)).unwrap();
    r.to(5.0);
    r.mapc(mb, b, ops(ONCE, PENDING)).unwrap();
    r.bits(mb, "EN DN IP");
    r.slave_bits("cam lock pending");
    r.to(8.0);
    r.mapc(
        mc,
        c,
        MapcOperands {
            cam_type: 1,
            ..ops(ONCE, IMMEDIATE)
        },
    )
    .unwrap();
    r.bits(mb, "EN DN");
    r.bits(ma, "EN DN");
    r.bits(mc, "EN DN IP AC");
    r.slave_bits("cam lock");
    assert_eq!(r.task.cam_profile(b).status(), 2);
    r.to(12.0);
    r.slave_at(10.0);
    r.to(19.0);
    r.bits(mc, "EN DN PC");
    r.slave_at(13.0);
    r.slave_bits("");
    for p in [a, b, c] {
        assert_eq!(r.task.cam_profile(p).status(), 2);
    }
}

#[test]
fn replace_and_restart_immediate_starts_at_the_cam_lock_position_from_the_slave() {
    let mut r = rig();
    let a = r.profile("A", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let b = r.profile("B", &[(0.0, 0.0), (100.0, 200.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    r.mapc(ma, a, ops(ONCE, IMMEDIATE)).unwrap();
    r.to(5.0);
    r.mapc(
        mb,
        b,
        MapcOperands {
            cam_type: 1,
            cam_lock_position: 50.0,
            ..ops(ONCE, IMMEDIATE)
        },
    )
    .unwrap();
    r.bits(ma, "EN DN");
    r.bits(mb, "EN DN IP AC");
    r.slave_bits("cam lock");
    r.to(7.0);
    r.slave_at(5.0 + 4.0);
    assert_eq!(r.task.cam_coordinate(r.slave), Some(52.0));
}

#[test]
fn replace_and_continue_immediate_continues_from_the_active_cam_point() {
    let mut r = rig();
    let a = r.profile("A", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let b = r.profile("B", &[(0.0, 0.0), (100.0, 200.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    r.mapc(ma, a, ops(ONCE, IMMEDIATE)).unwrap();
    r.to(5.0);
    r.slave_at(5.0);
    r.mapc(
        mb,
        b,
        MapcOperands {
            cam_type: 2,
            // Ignored for Replace and Continue, even outside the range.
            cam_lock_position: 1000.0,
            ..ops(ONCE, IMMEDIATE)
        },
    )
    .unwrap();
    r.bits(mb, "EN DN IP AC");
    // The replacement now defines the slave: B(6) = 12 (the sudden change).
    r.to(6.0);
    r.slave_at(12.0);
    assert_eq!(r.task.cam_coordinate(r.slave), Some(6.0));
}

#[test]
fn replace_and_restart_with_the_active_cam_locked() {
    // The spec's figure: Active persistent; replacement Forward Only / Forward
    // Only / Persistent, Master Lock 30, executed while the active is locked.
    let mut r = rig();
    let a = r.profile("A", &[(0.0, 0.0), (20.0, 10.0)], 0);
    let b = r.profile("B", &[(0.0, 0.0), (20.0, 40.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    let fwd = MapcOperands {
        master_direction: 1,
        ..ops(PERSISTENT, IMMEDIATE)
    };
    // (1) active start.
    r.mapc(ma, a, fwd).unwrap();
    r.slave_bits("cam lock");
    r.to(10.0);
    // (2) replacement start: pending set, cam and lock unchanged.
    r.mapc(
        mb,
        b,
        MapcOperands {
            cam_type: 1,
            master_lock_position: 30.0,
            execution_schedule: FORWARD,
            ..fwd
        },
    )
    .unwrap();
    r.bits(mb, "EN DN IP");
    r.slave_bits("cam lock pending");
    r.slave_at(5.0);
    // (3) active unlocked past its boundary.
    r.to(25.0);
    r.slave_at(10.0);
    r.slave_bits("cam pending");
    r.bits(ma, "EN DN IP AC");
    // (4) replacement at the Master Lock Position.
    r.to(32.0);
    r.slave_bits("cam lock");
    r.bits(ma, "EN DN");
    r.bits(mb, "EN DN IP AC");
    r.slave_at(14.0);
    // Until the master crosses the replacement's boundary.
    r.to(51.0);
    r.slave_at(50.0);
    r.slave_bits("cam");
    r.bits(mb, "EN DN IP AC");
}

#[test]
fn replace_and_restart_with_the_active_cam_unlocked() {
    let mut r = rig();
    let a = r.profile("A", &[(0.0, 0.0), (20.0, 10.0)], 0);
    let b = r.profile("B", &[(0.0, 0.0), (20.0, 40.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    r.mapc(ma, a, ops(PERSISTENT, IMMEDIATE)).unwrap();
    r.to(25.0);
    r.slave_bits("cam");
    r.mapc(
        mb,
        b,
        MapcOperands {
            cam_type: 1,
            master_direction: 1,
            ..ops(PERSISTENT, IMMEDIATE)
        },
    )
    .unwrap();
    r.slave_bits("cam lock");
    r.to(30.0);
    r.slave_at(20.0);
    r.to(46.0);
    r.slave_at(50.0);
    r.slave_bits("cam");
    r.bits(mb, "EN DN IP AC");
}

#[test]
fn replace_and_continue_with_the_active_cam_unlocked_by_a_master_reversal() {
    // Active Forward Only; the master reverses (unlocked); the replacement
    // (Forward Only schedule, Master Lock 10) is armed while reversing; it
    // takes over at 10 (.AC) but drives only from the reversal point on.
    let mut r = rig();
    let a = r.profile("A", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let b = r.profile("B", &[(0.0, 0.0), (100.0, 200.0)], 0);
    let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
    let fwd = MapcOperands {
        master_direction: 1,
        ..ops(PERSISTENT, IMMEDIATE)
    };
    r.mapc(ma, a, fwd).unwrap();
    r.to(20.0);
    r.slave_at(20.0);
    r.to(15.0);
    r.slave_bits("cam");
    r.to(5.0);
    r.mapc(
        mb,
        b,
        MapcOperands {
            cam_type: 2,
            master_lock_position: 10.0,
            execution_schedule: FORWARD,
            ..fwd
        },
    )
    .unwrap();
    r.slave_bits("cam pending");
    r.to(12.0);
    r.bits(mb, "EN DN IP AC");
    r.bits(ma, "EN DN");
    r.slave_bits("cam");
    // The slave stays where the active cam left it until the master is back
    // at the reversal point; then the replacement drives it.
    r.slave_at(20.0);
    r.to(18.0);
    r.slave_at(20.0);
    r.slave_bits("cam");
    r.to(22.0);
    r.slave_bits("cam lock");
    // Continues at cam point 20 → 22 on B's profile from A's reference: 2 × 22.
    r.slave_at(44.0);
}

#[test]
fn slip_clutch_holds_the_slave_and_picks_up_where_the_master_reversed() {
    for (direction, path, expected) in [
        // Forward only: holds at 10 while the master is behind it.
        (1, [10.0, 6.0, 9.0, 10.0, 14.0], [10.0, 10.0, 10.0, 10.0, 14.0]),
        // Bidirectional follows back.
        (0, [10.0, 6.0, 9.0, 10.0, 14.0], [10.0, 6.0, 9.0, 10.0, 14.0]),
        // Reverse only: ignores forward motion, follows back below the start.
        (2, [10.0, 6.0, -3.0, 2.0, -5.0], [0.0, 0.0, -3.0, -3.0, -5.0]),
    ] {
        let mut r = rig();
        let p = r.profile("Line", &[(-50.0, -50.0), (50.0, 50.0)], 0);
        let mi = r.task.add_instruction("MAPC_1");
        r.mapc(
            mi,
            p,
            MapcOperands {
                master_direction: direction,
                ..ops(ONCE, IMMEDIATE)
            },
        )
        .unwrap();
        for (m, s) in path.into_iter().zip(expected) {
            r.to(m);
            r.slave_at(s);
            let following = match direction {
                0 => true,
                1 => {
                    m >= path[..=path.iter().position(|&x| x == m).unwrap()]
                        .iter()
                        .cloned()
                        .fold(f64::MIN, f64::max)
                }
                _ => {
                    m <= path[..=path.iter().position(|&x| x == m).unwrap()]
                        .iter()
                        .cloned()
                        .fold(0.0, f64::min)
                }
            };
            assert_eq!(r.status().lock, following, "direction {direction} at {m}");
        }
    }
}

#[test]
fn slave_direction_same_opposite_reverse_unchanged() {
    let mut r = rig();
    let p = r.profile("Line", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    let run = |r: &mut Rig, direction: i32| {
        r.to(0.0);
        let before = r.slave_pos();
        r.mapc(
            mi,
            p,
            MapcOperands {
                direction,
                ..ops(ONCE, IMMEDIATE)
            },
        )
        .unwrap();
        r.to(10.0);
        r.slave_pos() - before
    };
    // First execution: Reverse → Opposite.
    assert_eq!(run(&mut r, 2), -10.0);
    assert_eq!(run(&mut r, 3), -10.0);
    assert_eq!(run(&mut r, 2), 10.0);
    assert_eq!(run(&mut r, 1), -10.0);
    assert_eq!(run(&mut r, 0), 10.0);
    assert_eq!(run(&mut r, 3), 10.0);
    // First execution: Unchanged → Same.
    let mut r2 = rig();
    let p = r2.profile("Line", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let mi = r2.task.add_instruction("MAPC_1");
    r2.mapc(
        mi,
        p,
        MapcOperands {
            direction: 3,
            ..ops(ONCE, IMMEDIATE)
        },
    )
    .unwrap();
    r2.to(10.0);
    r2.slave_at(10.0);
}

#[test]
fn scaling_stretches_master_and_slave() {
    let mut r = rig();
    let p = r.profile("Cam", &TABLE, 1);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(
        mi,
        p,
        MapcOperands {
            slave_scaling: 2.0,
            master_scaling: 4.0,
            ..ops(ONCE, IMMEDIATE)
        },
    )
    .unwrap();
    let prof = r.task.cam_profile(p).profile().unwrap().clone();
    for m in [13.0, 60.0, 100.0, 159.0] {
        r.to(m);
        r.slave_at(2.0 * prof.eval(m / 4.0).slave);
    }
}

#[test]
fn master_reference_command_or_actual() {
    for (reference, expected) in [(0, 7.0), (1, 5.0)] {
        let mut r = rig();
        let p = r.profile("Line", &[(0.0, 0.0), (100.0, 100.0)], 0);
        let mi = r.task.add_instruction("MAPC_1");
        r.mapc(
            mi,
            p,
            MapcOperands {
                master_reference: reference,
                ..ops(ONCE, IMMEDIATE)
            },
        )
        .unwrap();
        // Command 5 through MRP-free motion: jog the master, then feed an
        // actual position 2 ahead of the command.
        let jog = r.task.add_instruction("MAJ_1");
        r.task
            .maj(
                r.master,
                jog,
                &crate::task::instructions::maj::MajOperands {
                    speed: 100.0,
                    accel_rate: 1e6,
                    accel_units: 0,
                    ..Default::default()
                },
            )
            .unwrap();
        for _ in 0..5 {
            r.task.update();
        }
        let cmd = r.task.axis_state(r.master).command_position;
        assert!((cmd - 5.0).abs() < 0.01, "{cmd}");
        r.task.feed_actual_position(r.master, cmd + 2.0);
        r.task.update();
        let cmd = r.task.axis_state(r.master).command_position;
        let got = r.slave_pos();
        let want = if reference == 0 { cmd - 1.0 + 2.0 } else { cmd };
        assert!(
            (got - want).abs() < 1e-9,
            "reference {reference}: {got} vs {want} ({expected})"
        );
    }
}

#[test]
fn profile_status_counts_cams_in_and_out() {
    let mut task = MotionTask::new(DT).unwrap();
    let master = task.add_axis(axis("M"), 0.0).unwrap();
    let s1 = task.add_axis(axis("S1"), 0.0).unwrap();
    let s2 = task.add_axis(axis("S2"), 0.0).unwrap();
    let p = task.add_cam_profile("P", 8);
    let mccp = task.add_instruction("MCCP_1");
    let cam = [
        CamElement {
            master: 0.0,
            slave: 0.0,
            segment_type: 1,
        },
        CamElement {
            master: 10.0,
            slave: 5.0,
            segment_type: 1,
        },
    ];
    task.mccp(mccp, &cam, 2, 0.0, 0.0, p).unwrap();
    let (m1, m2) = (task.add_instruction("A"), task.add_instruction("B"));
    for (slave, mi) in [(s1, m1), (s2, m2)] {
        task.mapc(MapcCall {
            slave,
            master,
            motion_control: mi,
            cam_profile: p,
            operands: ops(CONTINUOUS, IMMEDIATE),
        })
        .unwrap();
    }
    assert_eq!(task.cam_profile(p).status(), 4);
    // MCCP refuses a profile in use (31).
    assert_eq!(task.mccp(mccp, &cam, 2, 0.0, 0.0, p).unwrap_err().err(), 31);
    assert!(task.motion_bits(mccp).er);
    assert_eq!(task.motion_bits(mccp).err, 31);
    let stop = task.add_instruction("MAS_1");
    task.mas(
        s1,
        stop,
        &crate::task::instructions::mas::MasOperands {
            stop_type: 8,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(task.cam_profile(p).status(), 3);
    task.reset_axis(s2);
    assert_eq!(task.cam_profile(p).status(), 2);
    task.mccp(mccp, &cam, 2, 0.0, 0.0, p).unwrap();
}

#[test]
fn mapc_errors_not_calculated_being_calculated_and_every_operand() {
    let mut r = rig();
    let p = r.task.add_cam_profile("Empty", 8);
    let mi = r.task.add_instruction("MAPC_1");
    assert_eq!(r.mapc(mi, p, MapcOperands::default()).unwrap_err().err(), 32);
    r.bits(mi, "EN ER");
    assert_eq!(r.task.motion_bits(mi).err, 32);
    let good = r.profile("Cam", &TABLE, 0);
    r.task.set_cam_profile_status(good, 1);
    assert_eq!(r.mapc(mi, good, MapcOperands::default()).unwrap_err().err(), 30);
    let good = r.profile("Cam2", &TABLE, 0);
    let d = MapcOperands::default();
    let cases = [
        (MapcOperands { direction: 4, ..d }, 3),
        (
            MapcOperands {
                slave_scaling: f64::NAN,
                ..d
            },
            5,
        ),
        (
            MapcOperands {
                master_scaling: 0.0,
                ..d
            },
            6,
        ),
        (MapcOperands { execution_mode: 3, ..d }, 7),
        (
            MapcOperands {
                execution_schedule: 5,
                ..d
            },
            8,
        ),
        (
            MapcOperands {
                master_lock_position: f64::INFINITY,
                ..d
            },
            9,
        ),
        (
            MapcOperands {
                cam_lock_position: 41.0,
                ..d
            },
            10,
        ),
        (MapcOperands { cam_type: 3, ..d }, 11),
        (
            MapcOperands {
                master_reference: 2,
                ..d
            },
            12,
        ),
        (
            MapcOperands {
                master_direction: -1,
                ..d
            },
            13,
        ),
    ];
    for (o, exerr) in cases {
        let e = r.mapc(mi, good, o).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (13, exerr));
        let b = r.task.motion_bits(mi);
        assert!(b.er && !b.dn && !b.ip);
        assert_eq!((b.err, b.exerr), (13, exerr));
        // A failed MAPC does not keep the profile.
        assert_eq!(r.task.cam_profile(good).status(), 2);
    }
    // Slave as its own master.
    let e = r
        .task
        .mapc(MapcCall {
            slave: r.slave,
            master: r.slave,
            motion_control: mi,
            cam_profile: good,
            operands: d,
        })
        .unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, 1));
}

#[test]
fn mccp_errors_reach_the_motion_instruction_tag() {
    let mut r = rig();
    let p = r.task.add_cam_profile("P", 8);
    let mi = r.task.add_instruction("MCCP_1");
    let mut cam: Vec<CamElement> = TABLE
        .iter()
        .map(|&(master, slave)| CamElement {
            master,
            slave,
            segment_type: 1,
        })
        .collect();
    cam[3].segment_type = 2;
    assert!(r.task.mccp(mi, &cam, 5, 0.0, 0.0, p).is_err());
    let b = r.task.motion_bits(mi);
    assert!(b.en && b.er && !b.dn);
    assert_eq!((b.err, b.exerr, b.segment), (28, 0, 3));
    r.task.rung_false(mi);
    assert!(!r.task.motion_bits(mi).en);
    assert_eq!(r.task.mccp(mi, &cam, 9, 0.0, 0.0, p).unwrap_err().err(), 26);
    assert_eq!(r.task.motion_bits(mi).exerr, 5);
}

#[test]
fn mrp_redefines_without_motion_and_keeps_the_following_error() {
    let mut r = rig();
    let mi = r.task.add_instruction("MRP_1");
    // Feed an actual 0.5 behind the command.
    r.task.feed_actual_position(r.slave, -0.5);
    r.task.mrp(r.slave, mi, 0, 1, 100.0).unwrap();
    r.bits(mi, "EN DN");
    let s = r.task.axis_state(r.slave);
    assert_eq!((s.command_position, s.actual_position), (100.0, 99.5));
    // The device keeps its own frame (−0.5); the axis' position is 99.5.
    let offset = r.task.position_offset(r.slave);
    assert_eq!(offset, 100.0);
    r.task.feed_actual_position(r.slave, -0.5 + offset);
    r.task.update();
    let s = r.task.axis_state(r.slave);
    assert_eq!(
        (s.command_position, s.actual_position, s.command_velocity),
        (100.0, 99.5, 0.0)
    );
    r.task.mrp(r.slave, mi, 0, 0, 10.0).unwrap();
    let s = r.task.axis_state(r.slave);
    assert_eq!((s.command_position, s.actual_position), (10.5, 10.0));
    assert_eq!(r.task.position_offset(r.slave), 10.5);
    assert_eq!(r.task.mrp(r.slave, mi, 0, 3, 0.0).unwrap_err().exerr(), 3);
    r.bits(mi, "EN ER");
}

#[test]
fn relative_mrp_while_jogging_is_exact() {
    let mut r = rig();
    let jog = r.task.add_instruction("MAJ_1");
    let mrp = r.task.add_instruction("MRP_1");
    r.task
        .maj(
            r.master,
            jog,
            &crate::task::instructions::maj::MajOperands {
                speed: 100.0,
                accel_rate: 1000.0,
                accel_units: 0,
                ..Default::default()
            },
        )
        .unwrap();
    for _ in 0..20 {
        r.task.update();
    }
    let before = r.task.axis_state(r.master);
    let mut twin = r.clone_task();
    r.task.mrp(r.master, mrp, 1, 1, -360.0).unwrap();
    for _ in 0..30 {
        r.task.update();
        twin.update();
        let (a, b) = (r.task.axis_state(r.master), twin.axis_state(r.master));
        assert!((a.command_position - (b.command_position - 360.0)).abs() < 1e-9);
        assert_eq!(a.command_velocity, b.command_velocity);
    }
    assert!(before.command_velocity > 0.0);
}

impl Rig {
    fn clone_task(&self) -> MotionTask {
        self.task.clone()
    }
}

#[test]
fn mrp_on_the_master_does_not_move_the_slave_and_on_the_slave_shifts_it() {
    let mut r = rig();
    let p = r.profile("Line", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    let mrp = r.task.add_instruction("MRP_1");
    r.mapc(mi, p, ops(ONCE, IMMEDIATE)).unwrap();
    r.to(10.0);
    r.slave_at(10.0);
    r.task.mrp(r.master, mrp, 0, 0, 1000.0).unwrap();
    // The device still reports 10 (now 1000) then 12 (1002).
    r.to(10.0);
    r.slave_at(10.0);
    r.to(12.0);
    r.slave_at(12.0);
    r.task.mrp(r.slave, mrp, 1, 1, 50.0).unwrap();
    r.to(13.0);
    r.slave_at(63.0);
}

#[test]
fn jog_and_stop_bits_and_motion() {
    let mut r = rig();
    let jog = r.task.add_instruction("MAJ_1");
    let stop = r.task.add_instruction("MAS_1");
    r.task
        .maj(
            r.master,
            jog,
            &crate::task::instructions::maj::MajOperands {
                direction: 1,
                speed: 50.0,
                accel_rate: 500.0,
                accel_units: 0,
                decel_rate: 250.0,
                decel_units: 0,
                ..Default::default()
            },
        )
        .unwrap();
    r.bits(jog, "EN DN IP");
    for _ in 0..20 {
        r.task.update();
    }
    assert_eq!(r.task.axis_state(r.master).command_velocity, -50.0);
    r.task
        .mas(
            r.master,
            stop,
            &crate::task::instructions::mas::MasOperands {
                stop_type: 1,
                change_decel: 1,
                decel_rate: 500.0,
                decel_units: 0,
            },
        )
        .unwrap();
    r.bits(jog, "EN DN");
    r.bits(stop, "EN DN IP");
    for _ in 0..9 {
        r.task.update();
    }
    assert!(r.task.axis_state(r.master).command_velocity < 0.0);
    r.task.update();
    r.task.update();
    r.bits(stop, "EN DN PC");
    assert_eq!(r.task.axis_state(r.master).command_velocity, 0.0);
    let p = r.task.axis_state(r.master).command_position;
    r.task.update();
    assert_eq!(r.task.axis_state(r.master).command_position, p);
}

#[test]
fn mas_position_cam_stops_the_slave_with_a_ramp() {
    let mut r = rig();
    let p = r.profile("Line", &[(0.0, 0.0), (1000.0, 1000.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    let stop = r.task.add_instruction("MAS_1");
    r.mapc(mi, p, ops(ONCE, IMMEDIATE)).unwrap();
    for k in 1..=10 {
        r.to(f64::from(k));
    }
    assert!((r.task.axis_state(r.slave).command_velocity - 100.0).abs() < 1e-6);
    r.task
        .mas(
            r.slave,
            stop,
            &crate::task::instructions::mas::MasOperands {
                stop_type: 8,
                change_decel: 1,
                decel_rate: 1000.0,
                decel_units: 0,
            },
        )
        .unwrap();
    r.bits(mi, "EN DN");
    r.slave_bits("");
    r.bits(stop, "EN DN IP");
    let mut last = r.slave_pos();
    for k in 11..=30 {
        r.to(f64::from(k));
        let s = r.slave_pos();
        assert!(s >= last);
        last = s;
    }
    r.bits(stop, "EN DN PC");
    // 10 + v²/2a = 10 + 5 (within one coarse update of travel).
    assert!((last - 15.0).abs() < 1.0, "{last}");
}

#[test]
fn one_driver_per_axis() {
    let mut table = AxisConfig {
        modulo_period: Some(360.0),
        ..axis("Table")
    };
    table.max_velocity = 720.0;
    let mut r = rig();
    let t = r.task.add_axis(table, 0.0).unwrap();
    let mm = r.task.add_move_modulo("Move", t);
    let p = r.profile("Line", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.task.set_move_modulo_inputs(
        mm,
        MoveModuloInputs {
            execute: true,
            position: 90.0,
            velocity: 90.0,
            direction: McDirection::Positive,
            buffer_mode: McBufferMode::Aborting,
            ..Default::default()
        },
    );
    r.task.update();
    assert!(r.task.outputs(mm).busy);
    // A cam aborts the move.
    r.task
        .mapc(MapcCall {
            slave: t,
            master: r.master,
            motion_control: mi,
            cam_profile: p,
            operands: ops(CONTINUOUS, IMMEDIATE),
        })
        .unwrap();
    assert!(r.task.outputs(mm).command_aborted);
    let held = r.task.axis_state(t).command_position;
    r.to(2.0);
    assert!((r.task.axis_state(t).command_position - (held + 2.0)).abs() < 1e-9);
    // A jog ends the cam.
    let jog = r.task.add_instruction("MAJ_1");
    r.task
        .maj(
            t,
            jog,
            &crate::task::instructions::maj::MajOperands {
                speed: 10.0,
                ..Default::default()
            },
        )
        .unwrap();
    r.bits(mi, "EN DN");
    assert_eq!(r.task.slave_cam_status(t), SlaveCamStatus::default());
    // A move ends the jog.
    r.task.set_move_modulo_inputs(mm, MoveModuloInputs::default());
    r.task.update();
    r.task.set_move_modulo_inputs(
        mm,
        MoveModuloInputs {
            execute: true,
            position: 180.0,
            velocity: 90.0,
            direction: McDirection::Positive,
            buffer_mode: McBufferMode::Aborting,
            ..Default::default()
        },
    );
    r.task.update();
    r.bits(jog, "EN DN");
    assert!(r.task.outputs(mm).active);
}

#[test]
fn cams_ignore_axis_limits_and_flag_them() {
    let mut r = rig();
    let p = r.profile("Steep", &[(0.0, 0.0), (1.0, 100.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(mi, p, ops(ONCE, IMMEDIATE)).unwrap();
    r.to(0.05);
    r.to(0.15);
    // 10 units in 0.01 s: 1000 units/s — at the limit, not above.
    assert!(!r.task.limits_exceeded(r.slave).velocity);
    r.to(0.35);
    // 20 units in 0.01 s: 2000 units/s, and the step in velocity is 1e5 units/s².
    r.slave_at(35.0);
    let f = r.task.limits_exceeded(r.slave);
    assert!(f.velocity && f.acceleration);
    r.to(0.36);
    assert!(!r.task.limits_exceeded(r.slave).velocity);
}

#[test]
fn a_one_shot_rung_clears_en_at_the_next_scan() {
    let mut r = rig();
    let p = r.profile("Line", &[(0.0, 0.0), (100.0, 100.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    r.mapc(mi, p, ops(ONCE, IMMEDIATE)).unwrap();
    r.task.rung_false_next_scan(mi);
    r.task.update();
    r.bits(mi, "EN DN IP AC");
    r.task.update();
    r.bits(mi, "DN IP AC");
    assert_eq!(r.task.find_cam_profile("line"), Some(p));
    assert_eq!(r.task.find_cam_profile("nope"), None);
    assert!(!r.task.is_cam_slave(r.slave));
    r.task.declare_cam_slave(r.slave);
    assert!(r.task.is_cam_slave(r.slave) && !r.task.is_cam_slave(r.master));
}

#[test]
fn mrp_during_a_move_shifts_the_move_with_the_axis() {
    let table = AxisConfig {
        modulo_period: Some(360.0),
        max_velocity: 720.0,
        ..axis("Table")
    };
    let mut task = MotionTask::new(DT).unwrap();
    let t = task.add_axis(table, 0.0).unwrap();
    let mm = task.add_move_modulo("Move", t);
    task.set_move_modulo_inputs(
        mm,
        MoveModuloInputs {
            execute: true,
            position: 270.0,
            velocity: 180.0,
            direction: McDirection::Positive,
            buffer_mode: McBufferMode::Aborting,
            ..Default::default()
        },
    );
    for _ in 0..50 {
        task.update();
    }
    let mut reference = task.clone();
    let mrp = task.add_instruction("MRP_1");
    task.mrp(t, mrp, 1, 1, -720.0).unwrap();
    assert_eq!(task.active_target(t), reference.active_target(t).map(|x| x - 720.0));
    for _ in 0..300 {
        task.update();
        reference.update();
        let (a, b) = (task.axis_state(t), reference.axis_state(t));
        assert!((a.command_position - (b.command_position - 720.0)).abs() < 1e-9);
        assert_eq!(a.command_velocity, b.command_velocity);
        assert_eq!(task.outputs(mm), reference.outputs(mm));
    }
    assert!(task.outputs(mm).done);
    assert!((task.axis_state(t).command_position - (270.0 - 720.0)).abs() < 1e-9);
}

#[test]
fn master_lock_position_on_a_modulo_master_ignores_the_turns_count() {
    let mut task = MotionTask::new(DT).unwrap();
    let master = task
        .add_axis(
            AxisConfig {
                modulo_period: Some(360.0),
                ..axis("Drum")
            },
            400.0,
        )
        .unwrap();
    let slave = task.add_axis(axis("Knife"), 0.0).unwrap();
    let p = task.add_cam_profile("Slope3", 4);
    let mccp = task.add_instruction("MCCP_1");
    let cam = [
        CamElement {
            master: 0.0,
            slave: 0.0,
            segment_type: 0,
        },
        CamElement {
            master: 100.0,
            slave: 300.0,
            segment_type: 0,
        },
    ];
    task.mccp(mccp, &cam, 2, 0.0, 0.0, p).unwrap();
    let mi = task.add_instruction("MAPC_1");
    task.mapc(MapcCall {
        slave,
        master,
        motion_control: mi,
        cam_profile: p,
        operands: MapcOperands {
            master_lock_position: 90.0,
            ..ops(ONCE, FORWARD)
        },
    })
    .unwrap();
    for (m, s, ac) in [(440.0, 0.0, false), (455.0, 15.0, true), (470.0, 60.0, true)] {
        task.feed_actual_position(master, m);
        task.update();
        assert!((task.axis_state(slave).command_position - s).abs() < 1e-9, "at {m}");
        assert_eq!(task.motion_bits(mi).ac, ac);
    }
}

#[test]
fn stopping_all_axes_ends_cams_and_jogs_with_a_ramp() {
    let mut r = rig();
    let p = r.profile("Line", &[(0.0, 0.0), (1000.0, 2000.0)], 0);
    let mi = r.task.add_instruction("MAPC_1");
    let jog = r.task.add_instruction("MAJ_1");
    r.mapc(
        mi,
        p,
        MapcOperands {
            master_reference: 1,
            ..ops(CONTINUOUS, IMMEDIATE)
        },
    )
    .unwrap();
    r.task
        .maj(
            r.master,
            jog,
            &crate::task::instructions::maj::MajOperands {
                speed: 100.0,
                ..Default::default()
            },
        )
        .unwrap();
    for _ in 0..50 {
        r.task.update();
    }
    assert!(r.task.axis_state(r.slave).command_velocity > 190.0);
    let report = r.task.stop_all_axes();
    assert_eq!(report.stopped_axes, vec![r.master, r.slave]);
    assert!(report.stopped_instructions.contains(&mi) && report.stopped_instructions.contains(&jog));
    r.bits(mi, "EN DN");
    r.bits(jog, "EN DN");
    r.slave_bits("");
    assert_eq!(r.task.cam_profile(p).status(), 2);
    assert!(r.task.is_stopping(r.slave) && r.task.is_stopping(r.master));
    for _ in 0..200 {
        r.task.update();
    }
    for axis in [r.master, r.slave] {
        assert_eq!(r.task.axis_state(axis).command_velocity, 0.0);
        assert!(!r.task.is_stopping(axis));
    }
}

/// Guards against a preloaded Pending cam (no cam active) surviving MAS
/// Position Cam and a stop of all axes with its Pending Status, `.IP` and
/// profile Status set.
#[test]
fn stops_end_a_preloaded_pending_cam() {
    for stop_all in [false, true] {
        let mut r = rig();
        let p = r.profile("Run", &[(0.0, 0.0), (10.0, 20.0)], 0);
        let mi = r.task.add_instruction("MAPC_P");
        r.mapc(mi, p, ops(ONCE, PENDING)).unwrap();
        r.bits(mi, "EN DN IP");
        r.slave_bits("pending");
        assert_eq!(r.task.cam_profile(p).status(), 3);
        if stop_all {
            let report = r.task.stop_all_axes();
            assert!(report.stopped_instructions.contains(&mi), "{report:?}");
        } else {
            let stop = r.task.add_instruction("MAS_1");
            let mas = crate::task::instructions::mas::MasOperands {
                stop_type: 8,
                ..Default::default()
            };
            r.task.mas(r.slave, stop, &mas).unwrap();
            r.bits(stop, "EN DN PC");
        }
        r.bits(mi, "EN DN");
        r.slave_bits("");
        assert_eq!(r.task.cam_profile(p).status(), 2);
        // A cam started afterwards finds no pending cam to hand over to.
        let a = r.task.add_instruction("MAPC_A");
        r.mapc(a, p, ops(ONCE, IMMEDIATE)).unwrap();
        r.to(12.0);
        r.bits(a, "EN DN PC");
        r.bits(mi, "EN DN");
        r.slave_bits("");
    }
}

/// Guards against MRP redefining an axis to a position outside its soft
/// travel limits without the fault the MAPC/MRP document names ("a software
/// overtravel fault is generated when the instruction is executed").
#[test]
fn mrp_outside_the_soft_travel_limits_raises_a_soft_overtravel_fault() {
    use crate::servo::{AxisFaults, FaultAction, MotionFaults};
    // (Type, Position Select, Position): each takes the actual position
    // (9.5, the command 10) outside [−100, 100].
    for (kind, select, position, bit) in [
        (0, 0, 100.5, MotionFaults::SOFT_TRAVEL_POSITIVE),
        (0, 1, -99.6, MotionFaults::SOFT_TRAVEL_NEGATIVE),
        (1, 0, 90.6, MotionFaults::SOFT_TRAVEL_POSITIVE),
        (1, 1, -109.6, MotionFaults::SOFT_TRAVEL_NEGATIVE),
    ] {
        let mut task = MotionTask::new(DT).unwrap();
        let cfg = AxisConfig {
            soft_travel_limits: Some((-100.0, 100.0)),
            ..axis("Lift")
        };
        let lift = task.add_axis(cfg, 10.0).unwrap();
        let mi = task.add_instruction("MRP_1");
        task.feed_actual_position(lift, 9.5);
        task.mrp(lift, mi, kind, select, position).unwrap();
        let b = task.motion_bits(mi);
        assert!(b.en && b.dn && !b.er, "{kind} {select} {position}");
        let s = task.axis_state(lift);
        assert!(s.actual_position > 100.0 || s.actual_position < -100.0);
        assert_eq!(task.motion_faults(lift).0, bit, "{kind} {select} {position}");
        assert_eq!(task.axis_faults(lift).0, AxisFaults::MOTION);
        // Stop Planner: the servo stays on.
        assert!(task.is_servo_on(lift));
    }
    // The bounds themselves are inside: no fault.
    let mut task = MotionTask::new(DT).unwrap();
    let cfg = AxisConfig {
        soft_travel_limits: Some((-100.0, 100.0)),
        soft_overtravel_action: FaultAction::StopDrive,
        ..axis("Lift")
    };
    let lift = task.add_axis(cfg, 10.0).unwrap();
    let mi = task.add_instruction("MRP_1");
    task.feed_actual_position(lift, 9.5);
    task.mrp(lift, mi, 0, 0, 100.0).unwrap();
    let s = task.axis_state(lift);
    assert_eq!((s.command_position, s.actual_position), (100.5, 100.0));
    task.mrp(lift, mi, 1, 1, -200.0).unwrap();
    let s = task.axis_state(lift);
    assert_eq!((s.command_position, s.actual_position), (-99.5, -100.0));
    assert!(task.motion_faults(lift).is_clear() && task.is_servo_on(lift));
    // One past the bound, with the Stop Drive action: the drive is off.
    task.mrp(lift, mi, 1, 1, -0.5).unwrap();
    assert!(task.motion_faults(lift).negative() && !task.is_servo_on(lift));
}

/// Guards against a master that moves more than one cycle of a Continuous
/// cam in one coarse update handing over to the Pending cam at the end of
/// the *last* cycle it entered instead of the cycle it was in.
#[test]
fn pending_cam_takes_over_at_the_end_of_the_current_cycle_even_after_a_long_step() {
    for (path, handover, expected) in [
        // Forward: cycle [0, 10) ends at 10; B (slope 2) runs from there.
        ([3.0, 25.0], 10.0, 10.0 + 2.0 * 15.0),
        // Reverse: cycle [0, 10) ends (backwards) at 0.
        ([3.0, -25.0], 0.0, 2.0 * -25.0),
    ] {
        let mut r = rig();
        let a = r.profile("Run", &[(0.0, 0.0), (10.0, 10.0)], 0);
        let b = r.profile("Fast", &[(0.0, 0.0), (10.0, 20.0)], 0);
        let (ma, mb) = (r.task.add_instruction("MAPC_A"), r.task.add_instruction("MAPC_B"));
        r.mapc(ma, a, ops(CONTINUOUS, IMMEDIATE)).unwrap();
        r.to(path[0]);
        r.slave_at(path[0]);
        r.mapc(mb, b, ops(CONTINUOUS, PENDING)).unwrap();
        r.to(path[1]);
        r.bits(ma, "EN DN");
        r.bits(mb, "EN DN IP AC");
        r.slave_bits("cam lock");
        // A's slave at the hand-over is the master position there (slope 1).
        assert_eq!(handover + 2.0 * (path[1] - handover), expected);
        r.slave_at(expected);
    }
}

/// A tiny Master Scaling (or a huge Slave Scaling) once overflowed the cam
/// coordinate and commanded the slave to NaN; a cam whose master points are
/// 1e-12 apart commanded 1.2e16 deg/s. The speed rule refuses them all at
/// MAPC (ERR 13, EXERR = Slave Scaling) and the slave holds.
#[test]
fn a_cam_no_drive_can_follow_is_refused_by_the_speed_rule_and_the_slave_holds() {
    let steep = [(0.0, 0.0), (120.0, 60.0), (120.000000000001, 120.0), (180.0, 120.0)];
    let line = [(0.0, 0.0), (10.0, 10.0)];
    for (points, master_scaling, slave_scaling, mode) in [
        (&line[..], 1e-300, 1.0, CONTINUOUS),
        (&line[..], 1.0, 1e308, ONCE),
        (&steep[..], 1.0, 1.0, ONCE),
    ] {
        let mut r = rig();
        let p = r.profile("Cam", points, 0);
        let mi = r.task.add_instruction("MAPC_1");
        let start = r.slave_pos();
        let e = r
            .mapc(
                mi,
                p,
                MapcOperands {
                    master_scaling,
                    slave_scaling,
                    ..ops(mode, IMMEDIATE)
                },
            )
            .unwrap_err();
        assert_eq!(e.err(), 13, "{e}");
        let b = r.task.motion_bits(mi);
        assert_eq!((b.err, b.exerr), (13, crate::mapc::operand::SLAVE_SCALING));
        r.bits(mi, "EN ER");
        r.slave_bits("");
        assert_eq!(r.task.cam_profile(p).status(), 2, "the profile is released");
        r.to(1e9);
        r.slave_at(start);
        assert_eq!(r.task.axis_state(r.slave).command_velocity, 0.0);
    }
}

/// The peak slope the speed rule uses is the profile's steepest, cubic
/// segments included (their vertex inside the segment).
#[test]
fn the_peak_slope_is_the_steepest_anywhere_in_the_profile() {
    let mut r = rig();
    let line = r.profile("Line", &[(0.0, 0.0), (10.0, 20.0), (20.0, 25.0)], 0);
    let profile = r.task.cam_profile(line).profile().unwrap().clone();
    assert_eq!(profile.peak_slope(), 2.0);
    let cubic = r.profile("Cubic", &[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)], 1);
    let profile = r.task.cam_profile(cubic).profile().unwrap().clone();
    let sampled = (0..=20_000)
        .map(|k| profile.eval(f64::from(k) * 1e-4).slope.abs())
        .fold(0.0, f64::max);
    assert!(
        (profile.peak_slope() - sampled).abs() < 1e-6,
        "{} vs {sampled}",
        profile.peak_slope()
    );
}

/// A conveyor's measured position drives a knife through a calculated
/// profile (Master Reference Actual): the profile is in use by one cam.
#[test]
fn a_measured_master_drives_its_cam_slave() {
    let mut task = MotionTask::new(0.004).unwrap();
    let conveyor = task
        .add_axis(AxisConfig::new("Conveyor", AxisKind::Linear), 0.0)
        .unwrap();
    let knife = task.add_axis(AxisConfig::new("Knife", AxisKind::Rotary), 0.0).unwrap();
    let cam = [
        CamElement {
            master: 0.0,
            slave: 0.0,
            segment_type: 0,
        },
        CamElement {
            master: 300.0,
            slave: 360.0,
            segment_type: 0,
        },
    ];
    let profile = task.add_cam_profile("KnifeProfile", 2);
    let mccp = task.add_instruction("MCCP_1");
    task.mccp(mccp, &cam, 2, 0.0, 0.0, profile).expect("valid cam");
    let mapc = task.add_instruction("MAPC_1");
    let operands = MapcOperands {
        execution_mode: 1,
        ..MapcOperands::default()
    };
    task.mapc(MapcCall {
        slave: knife,
        master: conveyor,
        motion_control: mapc,
        cam_profile: profile,
        operands,
    })
    .expect("calculated profile");
    assert_eq!(task.cam_profile(profile).status(), 3);
    task.feed_actual_position(conveyor, 450.0);
    task.update();
    assert!((task.axis_state(knife).command_position - 540.0).abs() < 1e-9);
}
