//! The MCT `Orientation` (`REAL[3]`, degrees about X1, X2, X3) and `Translation`
//! (`REAL[3]`, coordinate units) operands.
//!
//! # Conventions (reproducing the spec's rotation table)
//! With `Orientation = [a, b, c]` and `R = Rz(c)·Ry(b)·Rx(a)` (the table's
//! "matrix multiply order Z·(Y·X)", each `R` a right-handed rotation), the
//! position handed to the robot (the *target* Cartesian position, in the
//! robot's base frame) is
//!
//! ```text
//! target = Rᵀ · source + Translation
//! ```
//!
//! i.e. a positive angle turns the *point* clockwise about its axis (seen
//! from the axis' positive end) — the table's "90 (cw) around X" takes
//! `[1, 2, 3]` to `[1, 3, −2]` — and for several angles the point is turned
//! about X, then Y, then Z in the table's sense, which as point rotations is
//! `Rx(−a)·Ry(−b)·Rz(−c)` applied right to left. Every row of the table is a
//! test (`tests::spec_rotation_table_value_for_value`). The translation is
//! added after the rotation ("offset the target position along X1, X2,
//! X3"), so it is expressed in the robot frame. The source position of a
//! target position is the exact inverse, `source = R · (target − Translation)`.
//!
//! Sines and cosines of whole multiples of 90° are exact (0, ±1), so the
//! table's quarter turns give exact integers.

use super::Vec3;
use thiserror::Error;

/// Orientation and translation of the source frame relative to the robot
/// (the MCT `Orientation` and `Translation` operands).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    orientation_deg: Vec3,
    translation: Vec3,
    /// `R = Rz·Ry·Rx`, row-major.
    rotation: [[f64; 3]; 3],
}

/// An orientation or translation element that is not finite (Logix ERR 13,
/// parameter out of range, with the operand number as EXERR).
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum PlacementError {
    /// `Orientation[index]` is not finite.
    #[error("Orientation[{index}] = {value} must be finite")]
    Orientation {
        /// Element index 0–2.
        index: u8,
        /// Its value.
        value: f64,
    },
    /// `Translation[index]` is not finite.
    #[error("Translation[{index}] = {value} must be finite")]
    Translation {
        /// Element index 0–2.
        index: u8,
        /// Its value.
        value: f64,
    },
}

impl Default for Placement {
    fn default() -> Self {
        Self::new([0.0; 3], [0.0; 3]).expect("zero placement is valid")
    }
}

impl Placement {
    /// A placement from the operands: angles in degrees about X1, X2, X3 and
    /// offsets in coordinate units.
    ///
    /// # Examples
    /// The spec's "90 (cw) around X, then 90 (cw) around Y":
    /// ```
    /// use planner::mct::Placement;
    /// let p = Placement::new([90.0, 90.0, 0.0], [0.0; 3]).unwrap();
    /// assert_eq!(p.target_from_source([1.0, 2.0, 3.0]), [-3.0, 1.0, -2.0]);
    /// ```
    ///
    /// # Errors
    /// [`PlacementError`] naming the first non-finite element.
    pub fn new(orientation_deg: Vec3, translation: Vec3) -> Result<Self, PlacementError> {
        for (index, &value) in orientation_deg.iter().enumerate() {
            if !value.is_finite() {
                return Err(PlacementError::Orientation {
                    index: index as u8,
                    value,
                });
            }
        }
        for (index, &value) in translation.iter().enumerate() {
            if !value.is_finite() {
                return Err(PlacementError::Translation {
                    index: index as u8,
                    value,
                });
            }
        }
        let (sa, ca) = sin_cos_deg(orientation_deg[0]);
        let (sb, cb) = sin_cos_deg(orientation_deg[1]);
        let (sc, cc) = sin_cos_deg(orientation_deg[2]);
        let rx = [[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]];
        let ry = [[cb, 0.0, sb], [0.0, 1.0, 0.0], [-sb, 0.0, cb]];
        let rz = [[cc, -sc, 0.0], [sc, cc, 0.0], [0.0, 0.0, 1.0]];
        Ok(Self {
            orientation_deg,
            translation,
            rotation: mat_mul(&rz, &mat_mul(&ry, &rx)),
        })
    }

    /// The `Orientation` operand, degrees.
    pub fn orientation_deg(&self) -> Vec3 {
        self.orientation_deg
    }

    /// The `Translation` operand, coordinate units.
    pub fn translation(&self) -> Vec3 {
        self.translation
    }

    /// `Rᵀ · source + translation`: the robot-frame (target Cartesian)
    /// position of a source position.
    pub fn target_from_source(&self, source: Vec3) -> Vec3 {
        let v = self.unrotate(source);
        [
            v[0] + self.translation[0],
            v[1] + self.translation[1],
            v[2] + self.translation[2],
        ]
    }

    /// `R · (target − translation)`: the source position of a robot-frame
    /// position.
    pub fn source_from_target(&self, target: Vec3) -> Vec3 {
        self.rotate([
            target[0] - self.translation[0],
            target[1] - self.translation[1],
            target[2] - self.translation[2],
        ])
    }

    /// `Rᵀ · v`: a source-frame vector (velocity) in the robot frame.
    pub fn unrotate(&self, v: Vec3) -> Vec3 {
        let r = &self.rotation;
        [
            r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
            r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
            r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2],
        ]
    }

    /// `R · v`: a robot-frame vector (velocity) in the source frame.
    pub fn rotate(&self, v: Vec3) -> Vec3 {
        let r = &self.rotation;
        [
            r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
            r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
            r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
        ]
    }
}

fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

/// Sine and cosine of an angle in degrees, exact at whole multiples of 90°.
fn sin_cos_deg(deg: f64) -> (f64, f64) {
    let turn = deg.rem_euclid(360.0);
    if turn == 0.0 {
        (0.0, 1.0)
    } else if turn == 90.0 {
        (1.0, 0.0)
    } else if turn == 180.0 {
        (0.0, -1.0)
    } else if turn == 270.0 {
        (-1.0, 0.0)
    } else {
        deg.to_radians().sin_cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spec's table, verbatim: Logix V20 or greater, starting position
    /// [1, 2, 3].
    #[test]
    fn spec_rotation_table_value_for_value() {
        let start = [1.0, 2.0, 3.0];
        let table: [(Vec3, Vec3); 8] = [
            // 1 dimension rotation
            ([90.0, 0.0, 0.0], [1.0, 3.0, -2.0]),
            ([0.0, 90.0, 0.0], [-3.0, 2.0, 1.0]),
            ([0.0, 0.0, 90.0], [2.0, -1.0, 3.0]),
            // 2 dimension rotation
            ([90.0, 90.0, 0.0], [-3.0, 1.0, -2.0]),
            ([90.0, 0.0, 90.0], [2.0, 3.0, 1.0]),
            ([0.0, 90.0, 90.0], [-3.0, -1.0, 2.0]),
            // 3 dimension rotation
            ([90.0, 90.0, 90.0], [-3.0, 2.0, 1.0]),
            ([-90.0, -90.0, -90.0], [3.0, -2.0, 1.0]),
        ];
        for (orientation, expected) in table {
            let p = Placement::new(orientation, [0.0; 3]).unwrap();
            assert_eq!(p.target_from_source(start), expected, "Orient={orientation:?}");
            assert_eq!(p.source_from_target(expected), start, "Orient={orientation:?}");
        }
    }

    #[test]
    fn translation_is_added_after_the_rotation() {
        let p = Placement::new([0.0, 0.0, 90.0], [10.0, 20.0, 30.0]).unwrap();
        assert_eq!(p.target_from_source([1.0, 2.0, 3.0]), [12.0, 19.0, 33.0]);
        assert_eq!(p.source_from_target([12.0, 19.0, 33.0]), [1.0, 2.0, 3.0]);
    }

    #[test]
    fn arbitrary_angles_round_trip_and_keep_lengths() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for _ in 0..10_000 {
            let o = [0; 3].map(|_| rng.random_range(-720.0..720.0));
            let t = [0; 3].map(|_| rng.random_range(-5.0..5.0));
            let x = [0; 3].map(|_| rng.random_range(-5.0..5.0));
            let p = Placement::new(o, t).unwrap();
            let back = p.source_from_target(p.target_from_source(x));
            for i in 0..3 {
                assert!((back[i] - x[i]).abs() < 1e-12, "{o:?} {x:?} {back:?}");
            }
            let v = p.unrotate(x);
            let n = |v: Vec3| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!((n(v) - n(x)).abs() < 1e-12);
        }
    }

    #[test]
    fn non_finite_operands_are_refused_with_their_index() {
        assert!(matches!(
            Placement::new([0.0, f64::NAN, 0.0], [0.0; 3]),
            Err(PlacementError::Orientation { index: 1, .. })
        ));
        assert!(matches!(
            Placement::new([0.0; 3], [0.0, 0.0, f64::INFINITY]),
            Err(PlacementError::Translation { index: 2, .. })
        ));
    }
}
