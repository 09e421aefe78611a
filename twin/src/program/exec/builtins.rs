//! Timers, counters and one-shots on their structures in tag memory
//! (their rules: `scenes/README.md`, "Tasks, programs and routines").

use super::Exec;
use crate::program::ir::Builtin;
use crate::program::types::{Structure, Value};

impl Exec<'_> {
    pub(super) fn get(&self, base: usize, s: Structure, member: &str) -> Value {
        self.mem.slots[base + s.offset(member)]
    }

    pub(super) fn set(&mut self, base: usize, s: Structure, member: &str, v: Value) {
        self.mem.slots[base + s.offset(member)] = v;
    }

    pub(super) fn flag(&self, base: usize, s: Structure, member: &str) -> bool {
        self.get(base, s, member).truthy()
    }

    pub(super) fn builtin(&mut self, b: Builtin, base: usize) {
        use Structure as S;
        match b {
            Builtin::Tonr | Builtin::Tofr | Builtin::Rtor => self.timer(b, base),
            Builtin::Ctud => self.counter(base),
            Builtin::Osri | Builtin::Osfi => {
                let enabled = self.flag(base, S::OneShot, "EnableIn");
                self.set(base, S::OneShot, "EnableOut", Value::Bool(enabled));
                if !enabled {
                    return;
                }
                let input = self.flag(base, S::OneShot, "InputBit");
                let last = if self.first_scan {
                    b == Builtin::Osri
                } else {
                    self.flag(base, S::OneShot, "InputBitLast")
                };
                let out = if b == Builtin::Osri {
                    input && !last
                } else {
                    !input && last
                };
                self.set(base, S::OneShot, "OutputBit", Value::Bool(out));
                self.set(base, S::OneShot, "InputBitLast", Value::Bool(input));
            }
            Builtin::RTrig | Builtin::FTrig => {
                let clk = self.flag(base, S::Trig, "CLK");
                let m = self.flag(base, S::Trig, "M");
                let q = if b == Builtin::RTrig { clk && !m } else { !clk && m };
                self.set(base, S::Trig, "Q", Value::Bool(q));
                self.set(base, S::Trig, "M", Value::Bool(clk));
            }
            Builtin::Ton | Builtin::Tof => self.iec_timer(b == Builtin::Ton, base),
        }
    }

    /// Whole milliseconds since the timer's last execution while timing;
    /// the remainder carries to the next execution.
    pub(super) fn elapsed_ms(&mut self, base: usize, starting: bool) -> i64 {
        let s = Structure::Timer;
        let last = self.get(base, s, "LastScan_us").as_i64();
        if starting {
            self.set(base, s, "LastScan_us", Value::Int(self.now_us));
            return 0;
        }
        let ms = (self.now_us - last).max(0) / 1000;
        self.set(base, s, "LastScan_us", Value::Int(last + ms * 1000));
        ms
    }

    pub(super) fn timer(&mut self, b: Builtin, base: usize) {
        let s = Structure::Timer;
        let enabled = self.flag(base, s, "EnableIn");
        self.set(base, s, "EnableOut", Value::Bool(enabled));
        if !enabled {
            return;
        }
        let pre = self.get(base, s, "PRE").as_i64();
        let mut acc = self.get(base, s, "ACC").as_i64();
        let was_en = self.flag(base, s, "EN");
        let mut dn = self.flag(base, s, "DN");
        let enable = self.flag(base, s, "TimerEnable");
        if pre < 0 {
            self.set(base, s, "PresetInv", Value::Bool(true));
            self.set(base, s, "InstructFault", Value::Bool(true));
            self.set(base, s, "Status", Value::Int(1));
            self.set(base, s, "TT", Value::Bool(false));
            self.set(base, s, "DN", Value::Bool(false));
            self.set(base, s, "EN", Value::Bool(enable));
            return;
        }
        self.set(base, s, "PresetInv", Value::Bool(false));
        self.set(base, s, "InstructFault", Value::Bool(false));
        self.set(base, s, "Status", Value::Int(0));
        if self.flag(base, s, "Reset") {
            for m in ["ACC", "EN", "TT", "DN"] {
                self.set(base, s, m, if m == "ACC" { Value::Int(0) } else { Value::Bool(false) });
            }
            return;
        }
        let timing = match b {
            Builtin::Tofr => !enable && dn,
            _ => enable && !dn,
        };
        let starting = match b {
            Builtin::Tofr => was_en || !self.flag(base, s, "TT"),
            _ => !was_en || !self.flag(base, s, "TT"),
        };
        if timing {
            acc = (acc + self.elapsed_ms(base, starting)).min(pre);
        }
        match b {
            Builtin::Tonr => {
                if !enable {
                    acc = 0;
                }
                dn = enable && acc >= pre;
            }
            Builtin::Rtor => dn = dn || acc >= pre,
            _ => {
                if enable {
                    acc = 0;
                    dn = true;
                } else if acc >= pre {
                    dn = false;
                }
            }
        }
        let tt = match b {
            Builtin::Tofr => !enable && dn,
            _ => enable && !dn,
        };
        self.set(base, s, "ACC", Value::Int(acc));
        self.set(base, s, "EN", Value::Bool(enable));
        self.set(base, s, "DN", Value::Bool(dn));
        self.set(base, s, "TT", Value::Bool(tt));
    }

    pub(super) fn iec_timer(&mut self, on: bool, base: usize) {
        let s = Structure::IecTimer;
        let input = self.flag(base, s, "IN");
        let pt = self.get(base, s, "PT").as_i64().max(0);
        let running = self.flag(base, s, "Running");
        let timing = if on { input } else { !input };
        if timing && !running {
            self.set(base, s, "Start_us", Value::Int(self.now_us));
        }
        self.set(base, s, "Running", Value::Bool(timing));
        let et = if timing {
            ((self.now_us - self.get(base, s, "Start_us").as_i64()) / 1000).min(pt)
        } else {
            0
        };
        let done = timing && et >= pt;
        self.set(base, s, "ET", Value::Int(et));
        self.set(base, s, "Q", Value::Bool(if on { done } else { input || !done }));
    }

    pub(super) fn counter(&mut self, base: usize) {
        let s = Structure::Counter;
        let enabled = self.flag(base, s, "EnableIn");
        self.set(base, s, "EnableOut", Value::Bool(enabled));
        if !enabled {
            return;
        }
        let up = self.flag(base, s, "CUEnable");
        let down = self.flag(base, s, "CDEnable");
        if self.first_scan {
            self.set(base, s, "CU", Value::Bool(true));
            self.set(base, s, "CD", Value::Bool(true));
        }
        let mut acc = self.get(base, s, "ACC").as_i64();
        if self.flag(base, s, "Reset") {
            acc = 0;
            self.set(base, s, "OV", Value::Bool(false));
            self.set(base, s, "UN", Value::Bool(false));
        } else {
            if up && !self.flag(base, s, "CU") {
                if acc == i64::from(i32::MAX) {
                    self.set(base, s, "OV", Value::Bool(true));
                }
                acc = i64::from((acc as i32).wrapping_add(1));
            }
            if down && !self.flag(base, s, "CD") {
                if acc == i64::from(i32::MIN) {
                    self.set(base, s, "UN", Value::Bool(true));
                }
                acc = i64::from((acc as i32).wrapping_sub(1));
            }
        }
        self.set(base, s, "CU", Value::Bool(up));
        self.set(base, s, "CD", Value::Bool(down));
        self.set(base, s, "ACC", Value::Int(acc));
        let pre = self.get(base, s, "PRE").as_i64();
        self.set(base, s, "DN", Value::Bool(acc >= pre));
    }
}
