//! Fixed point's exact pre-test of a sphere (`src/scalar/ball.rs`): wherever it says a shadow
//! ray (a ray without a stored length) misses, the sphere's test, as it ran before the
//! pre-test, misses too: its `b` is above zero or its discriminant is not; and the sphere's
//! `nearest` gives what that test gave on every ray. Rays are drawn at random, most of them
//! aimed within a few steps of 2^-16 of a sphere's silhouette (where the margins decide),
//! over spheres from 2^-6 to 150 units and directions from 2^-12 to 60 units long.

use microray::object::sphere::Sphere;
use microray::scalar::I16F16;
use microray::{Ray, Scalar, Vec3};

/// A small deterministic generator (xorshift64*): the same rays on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn between(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.unit()
    }
    /// Spread over the octaves from 2^low to 2^high.
    fn octaves(&mut self, low: f64, high: f64) -> f64 {
        self.between(low, high).exp2()
    }
    fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [0; 3].map(|_| self.between(-1.0, 1.0));
            let n = v.iter().map(|c| c * c).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|c| c / n);
            }
        }
    }
}

fn fixed(v: [f64; 3]) -> Vec3<I16F16> {
    Vec3::new(
        I16F16::from_f64(v[0]),
        I16F16::from_f64(v[1]),
        I16F16::from_f64(v[2]),
    )
}

/// The old test's first step for a ray without a stored length: its direction divided by
/// its length (one wide reciprocal), and that reciprocal; `None` for a zero length.
fn unit_before(ray: &Ray<I16F16>) -> Option<(Vec3<I16F16>, <I16F16 as Scalar>::Wide)> {
    let inv = I16F16::wide_recip(ray.length().to_wide()?);
    let unit = Vec3::new(
        ray.dir.x.scale(inv),
        ray.dir.y.scale(inv),
        ray.dir.z.scale(inv),
    );
    Some((unit, inv))
}

/// The sphere's test of a ray without a stored length as it ran before the pre-test:
/// [`unit_before`], then `b` and the discriminant. `Some(missed)` when the length is above
/// zero (else it never gets that far), `missed` when `b > 0` or the discriminant is not
/// above zero.
fn missed_before(sphere: &Sphere<I16F16>, ray: &Ray<I16F16>) -> Option<bool> {
    let (unit, _) = unit_before(ray)?;
    let f = ray.base - sphere.center;
    let b = f.dot(unit);
    let perpendicular = f - unit * b;
    let discriminant = sphere.radius_squared - perpendicular.dot(perpendicular);
    Some(b > I16F16::ZERO || discriminant <= I16F16::ZERO)
}

/// `nearest` as it ran before the pre-test.
fn nearest_before(sphere: &Sphere<I16F16>, ray: &Ray<I16F16>, limit: I16F16) -> Option<I16F16> {
    let (unit, inv) = unit_before(ray)?;
    let t = sphere
        .nearest_unit(ray.base, unit, I16F16::UNBOUNDED)?
        .scale(inv);
    (t > I16F16::ZERO && t < limit).then_some(t)
}

/// What one kind of ray gave: how many rays, and how many the pre-test called misses.
#[derive(Default, Debug)]
struct Tally {
    rays: u32,
    called_misses: u32,
}

/// Draws `count` rays with `aim` (sphere centre, radius, rng) -> (base, dir), and checks
/// every one against the test as it was.
fn check(
    count: u32,
    seed: u64,
    aim: impl Fn(&mut Rng, [f64; 3], f64) -> ([f64; 3], [f64; 3]),
) -> Tally {
    let mut rng = Rng(seed);
    let mut tally = Tally::default();
    for _ in 0..count {
        let radius = rng.octaves(-6.0, 7.2);
        let center = [0; 3].map(|_| rng.between(-40.0, 40.0));
        let sphere = Sphere {
            center: fixed(center),
            radius: I16F16::from_f64(radius),
            radius_squared: I16F16::from_f64(radius * radius),
        };
        let (base, dir) = aim(&mut rng, center, radius);
        let ray = Ray::new(fixed(base), fixed(dir));
        let f = ray.base - sphere.center;
        let called = I16F16::misses_ball(f, ray.dir, ray.len, sphere.radius_squared);
        let limit = I16F16::from_f64(rng.octaves(-2.0, 8.0));
        assert_eq!(
            sphere.nearest(&ray, limit),
            nearest_before(&sphere, &ray, limit),
            "nearest changed: sphere {center:?} r {radius}, ray {base:?} + t {dir:?}"
        );
        tally.rays += 1;
        if called {
            tally.called_misses += 1;
            let missed = missed_before(&sphere, &ray);
            assert!(
                missed != Some(false),
                "pre-test called a hit a miss: sphere {center:?} r {radius}, ray {base:?} + t {dir:?}"
            );
        }
    }
    tally
}

/// A ray that passes the centre at `distance` (along a random perpendicular), from a base
/// `before` units ahead of that point along the ray (negative: past it), with a direction
/// `length` long.
fn passing(
    center: [f64; 3],
    way: [f64; 3],
    across: [f64; 3],
    distance: f64,
    before: f64,
    length: f64,
) -> ([f64; 3], [f64; 3]) {
    let closest = [0, 1, 2].map(|i| center[i] + across[i] * distance);
    let base = [0, 1, 2].map(|i| closest[i] - way[i] * before);
    (base, way.map(|c| c * length))
}

/// A unit vector perpendicular to `way`.
fn perpendicular(rng: &mut Rng, way: [f64; 3]) -> [f64; 3] {
    loop {
        let v = rng.direction();
        let along: f64 = (0..3).map(|i| v[i] * way[i]).sum();
        let p = [0, 1, 2].map(|i| v[i] - way[i] * along);
        let n = p.iter().map(|c| c * c).sum::<f64>().sqrt();
        if n > 0.1 {
            return p.map(|c| c / n);
        }
    }
}

#[test]
fn rays_grazing_the_silhouette_are_never_called_misses_wrongly() {
    // Within a few steps of 2^-16 (and of the margins, up to 2^-6 out) of the radius.
    let tally = check(600_000, 0x9e37_79b9_7f4a_7c15, |rng, center, radius| {
        let way = rng.direction();
        let across = perpendicular(rng, way);
        let offset = if rng.unit() < 0.5 {
            rng.between(-8.0, 8.0) / 65536.0
        } else {
            rng.octaves(-16.0, -6.0) * if rng.unit() < 0.5 { -1.0 } else { 1.0 }
        };
        // A third start within a few hundred steps of the closest point, where `b` is
        // about zero and its sign is the test's to give.
        let before = if rng.unit() < 1.0 / 3.0 {
            rng.between(-2.0, 2.0) * rng.octaves(-16.0, -6.0)
        } else {
            rng.between(-30.0, 60.0)
        };
        let length = rng.octaves(-12.0, 5.9);
        passing(center, way, across, radius + offset, before, length)
    });
    // Not vacuous: outside the silhouette, beyond the margins, many are called misses.
    assert_used(tally.called_misses > 50_000, &tally);
}

#[test]
fn rays_from_anywhere_are_never_called_misses_wrongly() {
    let tally = check(600_000, 0x2545_f491_4f6c_dd1d, |rng, center, radius| {
        let way = rng.direction();
        let across = perpendicular(rng, way);
        let distance = radius * rng.between(0.0, 3.0);
        let before = rng.between(-60.0, 60.0);
        let length = rng.octaves(-12.0, 5.9);
        passing(center, way, across, distance, before, length)
    });
    assert_used(tally.called_misses > 200_000, &tally);
}

#[test]
fn clear_misses_are_called_misses() {
    // Lines 1.25 radii and more from the centre, or leaving it behind, with a direction
    // at least a unit long, centres within 10 units of the origin on each axis: the
    // pre-test decides nearly all of them (what it is for).
    let mut rng = Rng(7);
    let mut tally = Tally::default();
    for _ in 0..100_000 {
        let radius = rng.octaves(-2.0, 3.0);
        let center = [0; 3].map(|_| rng.between(-10.0, 10.0));
        let way = rng.direction();
        let across = perpendicular(&mut rng, way);
        let leaving = rng.unit() < 0.3;
        let (distance, before) = if leaving {
            (
                radius * rng.between(0.0, 3.0),
                -radius - rng.between(0.5, 10.0),
            )
        } else {
            (radius * rng.between(1.25, 4.0), rng.between(-10.0, 10.0))
        };
        let (base, dir) = passing(
            center,
            way,
            across,
            distance,
            before,
            rng.between(1.0, 20.0),
        );
        let ray = Ray::new(fixed(base), fixed(dir));
        let f = ray.base - fixed(center);
        let rsq = I16F16::from_f64(radius * radius);
        tally.rays += 1;
        if I16F16::misses_ball(f, ray.dir, ray.len, rsq) {
            tally.called_misses += 1;
        }
    }
    let enough = f64::from(tally.called_misses) >= 0.99 * f64::from(tally.rays);
    assert_used(enough, &tally);
}

/// `enough`, in the shape built for speed; built for size (`cfg(microray_small)`, as
/// `MICRORAY_SMALL=1` makes it on the host) the pre-test is left out and calls nothing.
fn assert_used(enough: bool, tally: &Tally) {
    if cfg!(microray_small) {
        assert_eq!(tally.called_misses, 0, "{tally:?}");
    } else {
        assert!(enough, "{tally:?}");
    }
}

#[test]
fn the_floats_never_pre_test() {
    let (f, dir) = (Vec3::new(9.0, 9.0, 9.0), Vec3::new(1.0, 1.0, 1.0));
    assert!(!f64::misses_ball(f, dir, 0.0, 1.0));
    let (f, dir) = (Vec3::new(9.0f32, 9.0, 9.0), Vec3::new(1.0f32, 1.0, 1.0));
    assert!(!f32::misses_ball(f, dir, 0.0, 1.0));
}
