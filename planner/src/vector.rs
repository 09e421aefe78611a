//! Three-component vectors as plain arrays, for the few operations the
//! path geometry and the kinematics need (`[f64; 3]`, the type the public
//! API already uses for points and directions).

/// A point or direction in three coordinates.
pub(crate) type V3 = [f64; 3];

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn scale(a: V3, k: f64) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}

pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_is_orthogonal_and_right_handed() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(cross(x, y), [0.0, 0.0, 1.0]);
        let (a, b) = ([0.3, -1.2, 2.5], [4.0, 0.5, -0.7]);
        let c = cross(a, b);
        assert!(dot(c, a).abs() < 1e-12 && dot(c, b).abs() < 1e-12);
        assert!(norm(sub(add(sub(a, b), b), a)) < 1e-12);
        assert!((norm(scale([3.0, 4.0, 0.0], 2.0)) - 10.0).abs() < 1e-12);
    }
}
