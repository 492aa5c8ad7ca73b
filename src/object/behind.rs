//! Infinite planes that a row's primary rays meet only behind another (feature `batch`,
//! `f64`, with a plan): their tests are left to the rays that can see them.
//!
//! A row's rays run from the eye along `d = (a, dy, dz)`, `a` the pixel's `x` less the
//! eye's; only `a` changes along the row, and each ray's unit direction is `d / |d|`. An
//! infinite plane `N . p = N.point` a distance `D = N.point - N.eye` away is met at
//! `t = |d| D / (N . d)`, which is ahead of the eye where `D (N . d) > 0`, a condition
//! linear in `a`; the hit's `z` is `eye.z + dz D / (N . d)`, free of `|d|`. So where two
//! planes `A` and `B` are both ahead, `A` nearer, and `A`'s hit within the z rule, each a
//! condition linear in `a` once the signs are known, `B` cannot be a ray's closest hit:
//! the set of such `a` is an interval, and `B`'s test is needed only outside it. Where
//! that leaves one side of the row, `B` is tested only for the rays whose direction's `x`
//! lies there (`RowTest::PlaneAcross`; `x = a / |d|` grows with `a`); where it leaves none,
//! not at all (`RowTest::Miss`).
//!
//! Exact: the conditions hold with margins (`t` nearer by a relative `1e-9`, the z rule by
//! `1e-9` of the coordinates, the interval shrunk by `1e-7` of its ends), far beyond the
//! roundings of the rays' unit directions and of the tests (a few units in the last place).
//! At every `a` the nearest plane is not hidden (only a nearer one could hide it), so each
//! ray still tests the plane it would have found.

use super::{Object, RowEntry, RowOrigin, RowTest};
use crate::interval::Interval;
use crate::scalar::Scalar;

/// Relative margin by which the hiding plane must be nearer.
const NEARER: f64 = 1e-9;

/// Relative margin of the interval's ends and of the z rule.
const SHRINK: f64 = 1e-7;

/// The most intervals a plane's misses are joined from (beyond the row's two ends, behind
/// the eye, and hidden by each other plane of the row).
const MAX_SKIPS: usize = 3 + MAX_PLANES;

/// The most entries of a row looked at.
const MAX_PLANES: usize = 6;

/// Keeps the `a` of `interval` where `slope a + offset > 0` (the margins make `>= 0` the
/// same).
fn where_positive(interval: Interval, slope: f64, offset: f64) -> Interval {
    interval.where_nonnegative(offset, slope)
}

/// The interval shrunk by [`SHRINK`] of its ends' size at each finite end.
fn shrunk(interval: Interval) -> Interval {
    let margin = |v: f64| SHRINK * (1.0 + libm::fabs(v));
    let (lo, hi) = (interval.lo, interval.hi);
    Interval {
        lo: if lo.is_finite() { lo + margin(lo) } else { lo },
        hi: if hi.is_finite() { hi - margin(hi) } else { hi },
    }
}

/// A plane of the row, seen along it: `N . d = slope a + offset`, `D`.
#[derive(Clone, Copy, Debug)]
struct RowPlane {
    slope: f64,
    offset: f64,
    distance: f64,
}

impl RowPlane {
    fn of<S: Scalar>(object: &Object<S>, origin: &RowOrigin<S>, distance: S) -> Option<Self> {
        let plane = object.infinite_plane()?;
        let n = plane.unit_normal.to_f64();
        let (dy, dz) = (origin.dy.to_f64(), origin.dz.to_f64());
        Some(Self {
            slope: n.x,
            offset: n.y * dy + n.z * dz,
            distance: distance.to_f64(),
        })
    }

    /// The sign of `D` (the sign `N . d` must have for the plane to be ahead).
    fn sign(&self) -> f64 {
        if self.distance > 0.0 { 1.0 } else { -1.0 }
    }

    /// The `a` where the plane is ahead of the eye, clearly.
    fn ahead(&self) -> Interval {
        self.clearly(self.sign())
    }

    /// The `a` where the plane is behind the eye, clearly (its test misses).
    fn behind(&self) -> Interval {
        self.clearly(-self.sign())
    }

    /// The `a` where `s (N . d)` is clearly positive.
    fn clearly(&self, s: f64) -> Interval {
        let size = libm::fabs(self.slope) + libm::fabs(self.offset);
        where_positive(
            Interval::ALL,
            s * self.slope,
            s * self.offset - SHRINK * size,
        )
    }
}

/// The `a` where `front` hides `back`: both ahead, `front` nearer, its hit within the z
/// rule.
fn hidden(front: &RowPlane, back: &RowPlane, eye_z: f64, dz: f64, z_limit: f64) -> Interval {
    let (sf, sb) = (front.sign(), back.sign());
    let (df, db) = (libm::fabs(front.distance), libm::fabs(back.distance));
    if !(df > 0.0 && db > 0.0) {
        return Interval { lo: 1.0, hi: 0.0 };
    }
    let both = front.ahead().intersection(back.ahead());
    // Nearer: |Df| / pf < (1 - NEARER) |Db| / pb with pf = sf (N_f . d) > 0, pb likewise:
    // (1 - NEARER) |Db| pf - |Df| pb > 0.
    let k = (1.0 - NEARER) * db;
    let nearer = where_positive(
        both,
        k * sf * front.slope - df * sb * back.slope,
        k * sf * front.offset - df * sb * back.offset,
    );
    // z rule: eye.z + dz |Df| / pf <= z_limit - margin, pf > 0:
    // (z_limit - margin - eye.z) pf - dz |Df| >= 0 (kept strict).
    let room = z_limit - eye_z - SHRINK * (libm::fabs(z_limit) + libm::fabs(eye_z) + 1.0);
    shrunk(where_positive(
        nearer,
        room * sf * front.slope,
        room * sf * front.offset - dz * df,
    ))
}

/// Marks the row's infinite planes that only rays on one side of the row (or none) can
/// see, in `f64`; the row's rays have `a` within `span` (the image's width).
pub(crate) fn hide_behind<S: Scalar, const N: usize>(
    objects: &[Object<S>],
    row: &mut heapless::Vec<RowEntry<S>, N>,
    origin: &RowOrigin<S>,
    span: [f64; 2],
) {
    if !S::COURSE_ORDER {
        return;
    }
    let (eye_z, dz, z_limit) = (
        origin.eye.z.to_f64(),
        origin.dz.to_f64(),
        origin.z_limit.to_f64(),
    );
    let m = origin.dy_dz_squared();
    if !(m > 0.0) {
        return;
    }
    let plane_of = |entry: &RowEntry<S>| match entry.test {
        RowTest::Plane(distance) => {
            RowPlane::of(objects.get(usize::from(entry.index))?, origin, distance)
        }
        _ => None,
    };
    // Every plane seen before any entry changes (the first few: a row of more keeps its
    // other planes' tests).
    let mut planes = [None; MAX_PLANES];
    for (plane, entry) in planes.iter_mut().zip(row.iter()) {
        *plane = plane_of(entry);
    }
    // Beyond the row's ends, with a hair to spare: no ray to test.
    let [first, last] = span;
    let outside = [
        Interval {
            lo: f64::NEG_INFINITY,
            hi: first - SHRINK * (1.0 + libm::fabs(first)),
        },
        Interval {
            lo: last + SHRINK * (1.0 + libm::fabs(last)),
            hi: f64::INFINITY,
        },
    ];
    for (b, back) in planes.iter().enumerate() {
        let Some(back) = back else {
            continue;
        };
        // The `a` where its test misses: beyond the row, behind the eye, or hidden by
        // another plane.
        let mut skips = [Interval { lo: 1.0, hi: 0.0 }; MAX_SKIPS];
        let [left, right, behind, ..] = &mut skips;
        (*left, *right, *behind) = (outside[0], outside[1], back.behind());
        let mut count = 3;
        for (f, front) in planes.iter().enumerate() {
            if f == b || count == MAX_SKIPS {
                continue;
            }
            let Some(front) = front else {
                continue;
            };
            if let Some(slot) = skips.get_mut(count) {
                *slot = hidden(front, back, eye_z, dz, z_limit);
                count += 1;
            }
        }
        let skips = skips.get(..count).unwrap_or_default();
        // Skipped for every a < below and every a > above: the intervals joined from each
        // end of the line.
        let mut below = f64::NEG_INFINITY;
        let mut above = f64::INFINITY;
        for _ in 0..count {
            for iv in skips.iter().filter(|iv| iv.lo <= iv.hi) {
                if iv.lo <= below && iv.hi > below {
                    below = iv.hi;
                }
                if iv.hi >= above && iv.lo < above {
                    above = iv.lo;
                }
            }
        }
        let Some(entry) = row.get_mut(b) else {
            continue;
        };
        let RowTest::Plane(distance) = entry.test else {
            continue;
        };
        if below >= above {
            entry.test = RowTest::Miss;
        } else if below > outside[0].hi || above < outside[1].lo {
            // Tested for below <= a <= above (a part of the row, worth a test a ray), in the
            // direction's x (widened a hair).
            let lo = super::unit_x(below, m) - 1e-12;
            let hi = super::unit_x(above, m) + 1e-12;
            entry.test = RowTest::PlaneAcross {
                distance,
                lo: f32_below(lo),
                hi: f32_above(hi),
            };
        }
    }
}

/// An `f32` at or below `v` (`v` within -2..=2, where an `f32`'s step is below `2^-23`).
fn f32_below(v: f64) -> f32 {
    (v - 1e-6) as f32
}

/// An `f32` at or above `v` (as [`f32_below`]).
fn f32_above(v: f64) -> f32 {
    (v + 1e-6) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::plane::{PlaneDef, plane_init};
    use crate::vec3::Vec3;

    /// tplane4's two planes, a V open towards the eye: each is seen by the rays on its own
    /// side of the row (and a margin), and the rays outside meet the other one nearer.
    #[test]
    fn each_plane_of_a_v_is_tested_on_its_side() {
        let objects = [
            plane_init::<f64>(
                "l",
                0,
                &PlaneDef {
                    normal: [6.93, 0.0, 4.0],
                    point: [0.0; 3],
                },
                1.0,
            )
            .unwrap(),
            plane_init::<f64>(
                "r",
                0,
                &PlaneDef {
                    normal: [-6.93, 0.0, 4.0],
                    point: [4.0, 0.0, -6.93],
                },
                1.0,
            )
            .unwrap(),
        ];
        let eye = Vec3::new(4.0, 3.0, 8.0);
        let origin = RowOrigin {
            eye,
            dy: 0.0,
            dz: -8.0,
            z_limit: 0.01,
            columns: crate::camera::RowColumns::none(),
        };
        let mut row: heapless::Vec<RowEntry<f64>, 4> = objects
            .iter()
            .zip(0u16..)
            .map(|(o, index)| RowEntry {
                index,
                test: o.row_test(&origin),
            })
            .collect();
        hide_behind(&objects, &mut row, &origin, [-4.0, 4.0]);
        let bounds = |entry: &RowEntry<f64>| match entry.test {
            RowTest::PlaneAcross { lo, hi, .. } => Some((f64::from(lo), f64::from(hi))),
            _ => None,
        };
        let (left, right) = (bounds(&row[0]).unwrap(), bounds(&row[1]).unwrap());
        // The left plane for the rays left of the middle, the right for the others.
        assert!(left.0 < -0.4 && left.1 > 0.0 && left.1 < 0.01, "{left:?}");
        assert!(
            right.0 < 0.0 && right.0 > -0.01 && right.1 > 0.4,
            "{right:?}"
        );
        // Outside its bounds, a ray meets the other plane nearer.
        for a in [-3.9, -1.0, -0.02, 0.02, 1.0, 3.9] {
            let ray =
                crate::ray::Ray::with_length(eye, Vec3::new(a, 0.0, -8.0).unit().unwrap(), 1.0);
            let [tl, tr] = [&objects[0], &objects[1]].map(|o| o.hits(&ray, f64::INFINITY));
            for (k, (lo, hi)) in [left, right].into_iter().enumerate() {
                if !(ray.dir.x >= lo && ray.dir.x <= hi) {
                    let (own, other) = if k == 0 { (tl, tr) } else { (tr, tl) };
                    assert!(own.is_none() || other.unwrap() < own.unwrap(), "{a}");
                }
            }
        }
    }
}
