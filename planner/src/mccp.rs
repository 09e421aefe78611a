//! Motion Calculate Cam Profile (MCCP): CAM point arrays → calculated cam
//! profiles.
//!
//! # What the spec says, and how it is implemented
//! * A **CAM element** ([`CamElement`]) is a master/slave point pair and the
//!   interpolation type (`0` linear, `1` cubic) *from this point to the next*;
//!   the type of the last point is not used. Values are unitless (they take
//!   the master and slave axes' units when a MAPC runs the profile).
//! * `Length` is the number of cam elements used, from the start of the
//!   array slice given. A [`CamProfile`] can only be built by
//!   [`CamProfile::calculate`] (or validated by [`CamProfile::from_elements`]),
//!   so an invalid profile cannot exist.
//! * **Coefficients** `C0..C3` of each [`CamProfileElement`] describe the
//!   segment from that element to the next in **local master coordinates**:
//!   `slave(x) = C0 + C1·d + C2·d² + C3·d³` with `d = x − master[i]`
//!   (`0 ≤ d ≤ master[i+1] − master[i]`). The last element's coefficients are
//!   its slave value and zeros (the profile ends there).
//! * **Linear** segments are the straight line between their points.
//!   **Cubic** segments: each maximal run of consecutive cubic segments is a
//!   *clamped* cubic spline through its points (C² inside the run). Its end
//!   slopes are: `Start Slope` where the run starts at the first point,
//!   `End Slope` where it ends at the last point, and the slope of the
//!   adjacent linear segment everywhere else — so position *and* slope are
//!   continuous at every junction of a linear and a cubic segment. Start and
//!   End Slope do nothing when the first/last segment is linear (as the spec
//!   says).
//! * **Status** ([`CamProfileTag`]): 0 not calculated, 1 being calculated,
//!   2 calculated, n > 2 calculated and used by n − 2 MAPC instructions. MCCP
//!   refuses a profile with Status 1 ([`MccpError::CamProfileBeingCalculated`],
//!   ERR 30) or > 2 ([`MccpError::CamProfileBeingUsed`], ERR 31).
//! * **Errors** (the `ERR` numbers of the Logix motion error table):
//!   26 illegal cam length (EXERR = number of cam elements in the CAM array),
//!   27 illegal cam profile length (EXERR = number of cam points asked),
//!   28 illegal segment type, 29 master not ascending, 179 invalid element
//!   (NaN, infinity, or a coefficient that overflows) — each of 28/29/179 with
//!   `SEGMENT` = index of the offending element; 13 parameter out of range
//!   for a non-finite Start/End Slope (EXERR = operand number, 3 or 4).
//!
//! # Choices where the spec is silent
//! * Length < 2 or Length > the CAM array's size is error 26 (one point
//!   makes no profile).
//! * An element error (28, 29, 179) leaves the profile **not calculated**
//!   (Status 0, no profile): its old contents were already being
//!   overwritten. Operand errors (26, 27, 13: checked before the calculation
//!   starts) and errors 30 and 31 leave the profile untouched.
//! * The calculation completes inside the call (the spec: "in a single
//!   scan"), so Status 1 is only seen when a program writes it into the tag
//!   ([`CamProfileTag::set_status`]).
//! * Elements are checked in index order; in one element, a non-finite value
//!   (179) is reported before a bad type (28), before a non-ascending master
//!   (29).

use crate::catalogue::words::{motion_control, op};
use crate::catalogue::{Format, Kind, Operand, faceplate};
use crate::instruction::MotionInstructionBits;
use std::sync::Arc;
use thiserror::Error;

/// Interpolation from a cam point to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SegmentType {
    /// `0`: a straight line.
    #[default]
    Linear,
    /// `1`: part of a clamped cubic spline.
    Cubic,
}

impl SegmentType {
    /// The type for its DINT value (0 linear, 1 cubic).
    pub fn from_dint(value: i32) -> Option<Self> {
        match value {
            0 => Some(Self::Linear),
            1 => Some(Self::Cubic),
            _ => None,
        }
    }

    /// The DINT value (0 linear, 1 cubic).
    pub fn dint(self) -> i32 {
        match self {
            Self::Linear => 0,
            Self::Cubic => 1,
        }
    }
}

/// One element of a `CAM` array, as the program writes it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CamElement {
    /// Master value (unitless; master axis units under MAPC).
    pub master: f64,
    /// Slave value (unitless; slave axis units under MAPC).
    pub slave: f64,
    /// Segment type to the next point as a DINT (0 linear, 1 cubic); any other
    /// value is error 28.
    pub segment_type: i32,
}

/// One element of a calculated cam profile (`CAM_PROFILE_EXTENDED`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CamProfileElement {
    /// Master value of the point.
    pub master: f64,
    /// Slave value of the point.
    pub slave: f64,
    /// Interpolation to the next point.
    pub segment_type: SegmentType,
    /// `C0`: slave at the point (local coordinate d = 0).
    pub c0: f64,
    /// `C1`: slope dslave/dmaster at the point.
    pub c1: f64,
    /// `C2`: coefficient of d².
    pub c2: f64,
    /// `C3`: coefficient of d³.
    pub c3: f64,
}

/// Slave value and its master derivatives at one master value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CamPoint {
    /// Slave value.
    pub slave: f64,
    /// dslave/dmaster.
    pub slope: f64,
    /// d²slave/dmaster².
    pub curvature: f64,
}

/// A calculated, valid cam profile: ≥ 2 points, strictly ascending finite
/// masters, finite coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct CamProfile {
    elements: Vec<CamProfileElement>,
}

/// MCCP's operands (its catalogue entry is `task/instructions/mccp.rs`;
/// they are here beside the validation that names them).
pub const MCCP_OPERANDS: &[Operand] = &[
    motion_control(0),
    op("Cam", "CAM", Format::Array, Kind::Cam, 1),
    op("Length", "UINT", Format::ImmediateOrTag, Kind::Count, 2),
    op("Start Slope", "REAL", Format::ImmediateOrTag, Kind::Number, 3),
    op("End Slope", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
    op("Cam Profile", "CAM_PROFILE", Format::Array, Kind::CamProfile, 5),
];

/// Why MCCP failed (or a cam profile is invalid).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MccpError {
    /// ERR 26: Length is < 2 or more than the CAM array holds.
    #[error("illegal cam length {length}: the CAM array has {elements} elements (ERR 26)")]
    IllegalCamLength {
        /// Length asked.
        length: usize,
        /// Elements in the CAM array (EXERR).
        elements: usize,
    },
    /// ERR 27: the CAM_PROFILE array is too short for Length points.
    #[error("illegal cam profile length: {length} points do not fit a CAM_PROFILE of {capacity} (ERR 27)")]
    IllegalCamProfileLength {
        /// Points to generate (EXERR).
        length: usize,
        /// Elements in the CAM_PROFILE array.
        capacity: usize,
    },
    /// ERR 28: a segment type that is neither linear (0) nor cubic (1).
    #[error("illegal cam type {segment_type} in element [{segment}] (ERR 28)")]
    IllegalCamType {
        /// Element index (SEGMENT).
        segment: usize,
        /// The type found.
        segment_type: i32,
    },
    /// ERR 29: a master value not above the previous one.
    #[error("illegal cam order: master of element [{segment}] is not above the previous one (ERR 29)")]
    IllegalCamOrder {
        /// Element index (SEGMENT).
        segment: usize,
    },
    /// ERR 179: NaN, infinity or an overflowing coefficient.
    #[error("invalid cam profile element [{segment}]: not a finite number (ERR 179)")]
    InvalidCamProfileElement {
        /// Element index (SEGMENT).
        segment: usize,
    },
    /// ERR 30: the profile's Status is 1 (another MCCP is calculating it).
    #[error("cam profile is being calculated (Status 1) (ERR 30)")]
    CamProfileBeingCalculated,
    /// ERR 31: the profile's Status is > 2 (MAPC instructions use it).
    #[error("cam profile is in use by {users} cam(s) (Status {status}) (ERR 31)")]
    CamProfileBeingUsed {
        /// The Status found.
        status: u32,
        /// Cams using it (Status − 2).
        users: u32,
    },
    /// ERR 13: Start Slope (EXERR 3) or End Slope (EXERR 4) not finite.
    #[error("parameter out of range: operand {operand} = {value} (ERR 13)")]
    ParameterOutOfRange {
        /// Operand number on the faceplate, from 0 (EXERR).
        operand: i32,
        /// Its value.
        value: f64,
    },
}

impl crate::instruction::LogixFault for MccpError {
    fn err(&self) -> i32 {
        MccpError::err(self)
    }

    fn exerr(&self) -> i32 {
        MccpError::exerr(self)
    }

    fn segment(&self) -> i32 {
        MccpError::segment(self)
    }
}

impl MccpError {
    /// The `ERR` code.
    pub fn err(&self) -> i32 {
        match self {
            Self::IllegalCamLength { .. } => 26,
            Self::IllegalCamProfileLength { .. } => 27,
            Self::IllegalCamType { .. } => 28,
            Self::IllegalCamOrder { .. } => 29,
            Self::InvalidCamProfileElement { .. } => 179,
            Self::CamProfileBeingCalculated => 30,
            Self::CamProfileBeingUsed { .. } => 31,
            Self::ParameterOutOfRange { .. } => 13,
        }
    }

    /// The `EXERR` code (0 where the error has none).
    pub fn exerr(&self) -> i32 {
        match self {
            Self::IllegalCamLength { elements, .. } => to_i32(*elements),
            Self::IllegalCamProfileLength { length, .. } => to_i32(*length),
            Self::ParameterOutOfRange { operand, .. } => *operand,
            _ => 0,
        }
    }

    /// The `SEGMENT` field (0 where the error has none).
    pub fn segment(&self) -> i32 {
        match self {
            Self::IllegalCamType { segment, .. }
            | Self::IllegalCamOrder { segment }
            | Self::InvalidCamProfileElement { segment } => to_i32(*segment),
            _ => 0,
        }
    }

    /// Writes `.ER`, `ERR`, `EXERR` and `SEGMENT` into a MOTION_INSTRUCTION tag.
    pub fn write_to(&self, bits: &mut MotionInstructionBits) {
        bits.set_error(self.err(), self.exerr(), self.segment());
    }
}

fn to_i32(n: usize) -> i32 {
    i32::try_from(n).unwrap_or(i32::MAX)
}

impl CamProfile {
    /// MCCP's calculation: the profile of the first `length` elements of
    /// `cam`, with the boundary slopes `start_slope` and `end_slope`
    /// (dslave/dmaster; used only when the first/last segment is cubic).
    ///
    /// # Errors
    /// 26, 28, 29, 179 and 13 as listed in the module documentation.
    ///
    /// # Examples
    /// ```
    /// use planner::mccp::{CamElement, CamProfile};
    /// let point = |master, slave, segment_type| CamElement { master, slave, segment_type };
    /// // A cubic segment into two linear ones.
    /// let cam = [point(0.0, 0.0, 1), point(10.0, 30.0, 0), point(20.0, 35.0, 0)];
    /// let profile = CamProfile::calculate(&cam, 3, 0.0, 0.0)?;
    /// assert_eq!(profile.eval(15.0).slave, 32.5);
    /// // The cubic run ends with the slope of the line after it.
    /// assert!((profile.eval(10.0).slope - 0.5).abs() < 1e-12);
    /// # Ok::<(), planner::mccp::MccpError>(())
    /// ```
    pub fn calculate(cam: &[CamElement], length: usize, start_slope: f64, end_slope: f64) -> Result<Self, MccpError> {
        check_operands(cam.len(), length, start_slope, end_slope)?;
        let cam = &cam[..length];
        let mut types = Vec::with_capacity(length);
        for (i, e) in cam.iter().enumerate() {
            if !(e.master.is_finite() && e.slave.is_finite()) {
                return Err(MccpError::InvalidCamProfileElement { segment: i });
            }
            let t = if i + 1 == length {
                // The last point's type is never used; any value is accepted.
                SegmentType::from_dint(e.segment_type).unwrap_or_default()
            } else {
                SegmentType::from_dint(e.segment_type).ok_or(MccpError::IllegalCamType {
                    segment: i,
                    segment_type: e.segment_type,
                })?
            };
            if i > 0 && e.master <= cam[i - 1].master {
                return Err(MccpError::IllegalCamOrder { segment: i });
            }
            types.push(t);
        }
        let x: Vec<f64> = cam.iter().map(|e| e.master).collect();
        let y: Vec<f64> = cam.iter().map(|e| e.slave).collect();
        let slopes = knot_slopes(&x, &y, &types, start_slope, end_slope);
        let mut elements = Vec::with_capacity(length);
        for i in 0..length {
            let mut e = CamProfileElement {
                master: x[i],
                slave: y[i],
                segment_type: types[i],
                c0: y[i],
                c1: 0.0,
                c2: 0.0,
                c3: 0.0,
            };
            if i + 1 < length {
                let h = x[i + 1] - x[i];
                let d = (y[i + 1] - y[i]) / h;
                match types[i] {
                    SegmentType::Linear => e.c1 = d,
                    SegmentType::Cubic => {
                        let (k0, k1) = (slopes[i], slopes[i + 1]);
                        e.c1 = k0;
                        e.c2 = (3.0 * d - 2.0 * k0 - k1) / h;
                        e.c3 = (k0 + k1 - 2.0 * d) / (h * h);
                    }
                }
                if !(h.is_finite() && [e.c1, e.c2, e.c3].iter().all(|c| c.is_finite())) {
                    return Err(MccpError::InvalidCamProfileElement { segment: i });
                }
            }
            elements.push(e);
        }
        Ok(Self { elements })
    }

    /// Validates a profile given element by element (a `CAM_PROFILE_EXTENDED`
    /// array written by a program or the Cam Profile Editor).
    ///
    /// # Errors
    /// 26 for fewer than 2 elements; 179 for a non-finite value, 29 for a
    /// non-ascending master, each with `SEGMENT` = the element index.
    pub fn from_elements(elements: Vec<CamProfileElement>) -> Result<Self, MccpError> {
        if elements.len() < 2 {
            return Err(MccpError::IllegalCamLength {
                length: elements.len(),
                elements: elements.len(),
            });
        }
        for (i, e) in elements.iter().enumerate() {
            if ![e.master, e.slave, e.c0, e.c1, e.c2, e.c3]
                .iter()
                .all(|v| v.is_finite())
            {
                return Err(MccpError::InvalidCamProfileElement { segment: i });
            }
            if i > 0 && e.master <= elements[i - 1].master {
                return Err(MccpError::IllegalCamOrder { segment: i });
            }
        }
        Ok(Self { elements })
    }

    /// The calculated elements (one per cam point).
    pub fn elements(&self) -> &[CamProfileElement] {
        &self.elements
    }

    /// First and last master values.
    pub fn master_range(&self) -> (f64, f64) {
        (self.elements[0].master, self.elements[self.elements.len() - 1].master)
    }

    /// The steepest |slave slope| (slave units per master unit) anywhere in
    /// the profile: each segment's derivative `C1 + 2·C2·d + 3·C3·d²` at
    /// its ends and at its vertex when that lies inside. Infinite or NaN
    /// only if a coefficient is.
    pub fn peak_slope(&self) -> f64 {
        self.elements
            .windows(2)
            .map(|pair| {
                let (e, h) = (&pair[0], pair[1].master - pair[0].master);
                let slope = |d: f64| e.c1 + 2.0 * e.c2 * d + 3.0 * e.c3 * d * d;
                let vertex = if e.c3 != 0.0 { -e.c2 / (3.0 * e.c3) } else { f64::NAN };
                let mut peak = slope(0.0).abs().max(slope(h).abs());
                if vertex > 0.0 && vertex < h {
                    peak = peak.max(slope(vertex).abs());
                }
                peak
            })
            .fold(0.0, |a: f64, b| if b.is_nan() { f64::NAN } else { a.max(b) })
    }

    /// First and last slave values.
    pub fn slave_range(&self) -> (f64, f64) {
        (self.elements[0].slave, self.elements[self.elements.len() - 1].slave)
    }

    /// Slave value, slope and curvature at `master`, clamped into the master
    /// range (outside it: the end value, with the end segment's derivatives).
    pub fn eval(&self, master: f64) -> CamPoint {
        let (x0, xn) = self.master_range();
        let x = master.clamp(x0, xn);
        let n = self.elements.len();
        let i = self.elements.partition_point(|e| e.master <= x).clamp(1, n - 1) - 1;
        let e = &self.elements[i];
        let d = x - e.master;
        CamPoint {
            slave: e.c0 + d * (e.c1 + d * (e.c2 + d * e.c3)),
            slope: e.c1 + d * (2.0 * e.c2 + 3.0 * e.c3 * d),
            curvature: 2.0 * e.c2 + 6.0 * e.c3 * d,
        }
    }
}

/// The operand checks made before any element is read: Length (26) and the
/// slopes (13).
fn check_operands(elements: usize, length: usize, start_slope: f64, end_slope: f64) -> Result<(), MccpError> {
    if length < 2 || length > elements {
        return Err(MccpError::IllegalCamLength { length, elements });
    }
    for (operand, value) in [
        (faceplate(MCCP_OPERANDS, "Start Slope"), start_slope),
        (faceplate(MCCP_OPERANDS, "End Slope"), end_slope),
    ] {
        if !value.is_finite() {
            return Err(MccpError::ParameterOutOfRange { operand, value });
        }
    }
    Ok(())
}

/// Slopes at every knot: exact for linear segments' ends, from a clamped
/// spline for each cubic run.
fn knot_slopes(x: &[f64], y: &[f64], types: &[SegmentType], start_slope: f64, end_slope: f64) -> Vec<f64> {
    let n = x.len();
    let secant = |i: usize| (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
    let mut k = vec![0.0; n];
    let mut i = 0;
    while i + 1 < n {
        if types[i] == SegmentType::Linear {
            i += 1;
            continue;
        }
        let a = i;
        let mut b = i;
        while b + 1 < n && types[b] == SegmentType::Cubic {
            b += 1;
        }
        // Cubic segments a..b (knots a..=b).
        let ka = if a == 0 { start_slope } else { secant(a - 1) };
        let kb = if b == n - 1 { end_slope } else { secant(b) };
        clamped_run(&x[a..=b], &y[a..=b], ka, kb, &mut k[a..=b]);
        i = b;
    }
    k
}

/// Clamped cubic spline knot slopes (Thomas algorithm on the standard
/// slope-continuity equations; the matrix is strictly diagonally dominant).
fn clamped_run(x: &[f64], y: &[f64], ka: f64, kb: f64, k: &mut [f64]) {
    let m = x.len();
    k[0] = ka;
    k[m - 1] = kb;
    if m == 2 {
        return;
    }
    // Unknowns k[1..m-1]; row j (knot j): h_j k_{j-1} + 2(h_{j-1}+h_j) k_j + h_{j-1} k_{j+1} = r_j
    // with h_{j-1} = x_j − x_{j−1}, h_j = x_{j+1} − x_j.
    let inner = m - 2;
    let mut c_prime = vec![0.0; inner];
    let mut d_prime = vec![0.0; inner];
    for r in 0..inner {
        let j = r + 1;
        let hl = x[j] - x[j - 1];
        let hr = x[j + 1] - x[j];
        let dl = (y[j] - y[j - 1]) / hl;
        let dr = (y[j + 1] - y[j]) / hr;
        let lower = hr;
        let diag = 2.0 * (hl + hr);
        let upper = hl;
        let mut rhs = 3.0 * (hr * dl + hl * dr);
        if j == 1 {
            rhs -= lower * ka;
        }
        if j == m - 2 {
            rhs -= upper * kb;
        }
        let (denom, prev_d) = if r == 0 {
            (diag, 0.0)
        } else {
            (diag - lower * c_prime[r - 1], d_prime[r - 1])
        };
        c_prime[r] = if j == m - 2 { 0.0 } else { upper / denom };
        d_prime[r] = if r == 0 {
            rhs / denom
        } else {
            (rhs - lower * prev_d) / denom
        };
    }
    k[m - 2] = d_prime[inner - 1];
    for r in (0..inner - 1).rev() {
        k[r + 1] = d_prime[r] - c_prime[r] * k[r + 2];
    }
}

/// A `CAM_PROFILE` tag: an array of `capacity` elements, its first element's
/// Status, and the profile once calculated. Shared by MCCP (which writes it)
/// and MAPC (which counts itself in and out of Status).
#[derive(Debug, Clone, PartialEq)]
pub struct CamProfileTag {
    capacity: usize,
    status: u32,
    profile: Option<Arc<CamProfile>>,
}

impl CamProfileTag {
    /// An uncalculated tag (Status 0) of `capacity` elements.
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity,
            status: 0,
            profile: None,
        }
    }

    /// Number of elements of the array.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Status of the first element (0, 1, 2, or 2 + users).
    pub fn status(&self) -> u32 {
        self.status
    }

    /// Writes Status, as a program writing `Profile[0].Status` would. Writing
    /// 0 or 1 makes the profile uncalculated (its contents are dropped).
    pub fn set_status(&mut self, status: u32) {
        self.status = status;
        if status < 2 {
            self.profile = None;
        }
    }

    /// The calculated profile, if any.
    pub fn profile(&self) -> Option<&Arc<CamProfile>> {
        self.profile.as_ref()
    }

    /// Executes MCCP into this tag.
    ///
    /// # Errors
    /// 30 (Status 1), 31 (Status > 2), 27 (`length` > capacity) and every
    /// error of [`CamProfile::calculate`].
    pub fn calculate(
        &mut self,
        cam: &[CamElement],
        length: usize,
        start_slope: f64,
        end_slope: f64,
    ) -> Result<(), MccpError> {
        match self.status {
            1 => return Err(MccpError::CamProfileBeingCalculated),
            s if s > 2 => {
                return Err(MccpError::CamProfileBeingUsed {
                    status: s,
                    users: s - 2,
                });
            }
            _ => {}
        }
        // Operand errors (26, 27, 13) leave the tag as it was: nothing has
        // been written yet.
        check_operands(cam.len(), length, start_slope, end_slope)?;
        if length > self.capacity {
            return Err(MccpError::IllegalCamProfileLength {
                length,
                capacity: self.capacity,
            });
        }
        self.status = 1;
        self.profile = None;
        match CamProfile::calculate(cam, length, start_slope, end_slope) {
            Ok(p) => {
                self.profile = Some(Arc::new(p));
                self.status = 2;
                Ok(())
            }
            Err(e) => {
                self.status = 0;
                Err(e)
            }
        }
    }

    /// A MAPC takes the profile: Status + 1.
    ///
    /// # Errors
    /// Status 0 (not calculated) or 1 (being calculated), returned as the
    /// Status found.
    pub fn acquire(&mut self) -> Result<Arc<CamProfile>, u32> {
        match (&self.profile, self.status) {
            (Some(p), s) if s >= 2 => {
                self.status = s.saturating_add(1);
                Ok(p.clone())
            }
            (_, s) => Err(s),
        }
    }

    /// A cam using the profile ended: Status − 1 (never below 2 while
    /// calculated).
    pub fn release(&mut self) {
        if self.status > 2 {
            self.status -= 1;
        }
    }
}

#[cfg(test)]
mod tests;
