//! Property tests of the intersection routines in every number type: a reported hit is
//! ahead of the ray and on the surface within a stated bound, its normal is unit length
//! within a bound, a ray aimed at a sphere's centre from outside hits it, a ray leaving a
//! surface does not come back to it, and no finite input makes anything panic or give NaN.
//!
//! Bounds are relative to the size of the geometry involved (`size`: the largest of the
//! ray base's and the object's coordinates and radius). They are stated per type below and
//! quoted in docs/number-types.md's stability section.

use microray::object::{ObjectDef, RectDef};
use microray::scalar::I16F16;
use microray::{CameraDef, Hit, MaterialDef, Object, Ray, Scalar, Scene, Vec3};
use proptest::prelude::*;

const CAMERA: CameraDef<'static> = CameraDef::new("c", [8, 6], [8.0, 6.0], [4.0, 3.0, 6.0]);
const MATERIALS: [MaterialDef<'static>; 1] = [MaterialDef::new("m")];

/// Per type: how far a hit may lie off the surface and how far a normal's length may be
/// from 1, as fractions of the geometry's size (off the surface) and absolute (normal).
trait Bounds: Scalar {
    const OFF_SURFACE: f64;
    const NORMAL_LENGTH: f64;
}
impl Bounds for f64 {
    const OFF_SURFACE: f64 = 1e-13;
    const NORMAL_LENGTH: f64 = 1e-15;
}
impl Bounds for f32 {
    const OFF_SURFACE: f64 = 2e-6;
    const NORMAL_LENGTH: f64 = 1e-6;
}
impl Bounds for I16F16 {
    // A few steps of 2^-16 in every coordinate, at sizes up to 100.
    const OFF_SURFACE: f64 = 2e-4;
    const NORMAL_LENGTH: f64 = 1.5e-4;
}

/// One object, alone in a scene (scale 1: every value here is within every type's range).
fn object<S: Scalar>(def: ObjectDef<'_>) -> Option<Object<S>> {
    let scene: Scene<'_, S, 1, 1, 0, 0, 8> =
        Scene::from_defs(&CAMERA, &MATERIALS, &[], &[], &[def]).ok()?;
    (scene.scale() == 1.0).then(|| scene.objects()[0].clone())
}

/// A ray in `S` from `base` along `dir` (normalised in `S`).
fn ray<S: Scalar>(base: [f64; 3], dir: [f64; 3]) -> Option<Ray<S>> {
    let dir = Vec3::<S>::from_f64(dir).unit()?;
    Some(Ray::new(Vec3::from_f64(base), dir))
}

fn size(values: &[[f64; 3]], extra: f64) -> f64 {
    values
        .iter()
        .flatten()
        .fold(extra.abs(), |m, v| m.max(v.abs()))
        .max(1.0)
}

/// What every hit must satisfy: ahead, the point on the ray, a unit normal.
fn check_hit<S: Bounds>(ray: &Ray<S>, hit: &Hit<S>, size: f64) -> Result<(), TestCaseError> {
    let t = hit.t.to_f64();
    prop_assert!(t > 0.0, "t = {t}");
    let n = hit.normal.to_f64();
    let length = n.dot(n).sqrt();
    prop_assert!(
        (length - 1.0).abs() <= S::NORMAL_LENGTH,
        "{}: |normal| = {length}",
        S::NAME
    );
    // The point is the ray's point at t, as the type computes it.
    let expected = ray.at(hit.t).to_f64();
    prop_assert!(
        (hit.point.to_f64() - expected).length_f64() <= S::OFF_SURFACE * size,
        "{}: point off the ray",
        S::NAME
    );
    Ok(())
}

trait Length {
    fn length_f64(self) -> f64;
    fn arr(self) -> [f64; 3];
}
impl Length for Vec3<f64> {
    fn length_f64(self) -> f64 {
        self.dot(self).sqrt()
    }
    fn arr(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

fn coordinate() -> impl Strategy<Value = f64> {
    -50.0f64..50.0
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [coordinate(), coordinate(), coordinate()]
}

fn direction() -> impl Strategy<Value = [f64; 3]> {
    [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0].prop_filter("a direction", |d| {
        d.iter().map(|c| c * c).sum::<f64>() > 1e-2
    })
}

fn sphere_case<S: Bounds>(
    center: [f64; 3],
    radius: f64,
    base: [f64; 3],
    dir: [f64; 3],
) -> Result<(), TestCaseError> {
    let Some(sphere) = object::<S>(ObjectDef::sphere("s", "m", center, radius)) else {
        return Ok(());
    };
    let size = size(&[center, base], radius);
    let c = Vec3::from_array(center);
    let on_sphere = |p: Vec3<f64>| ((p - c).length_f64() - radius).abs();
    if let Some(r) = ray::<S>(base, dir)
        && let Some(hit) = sphere.hit(&r)
    {
        check_hit(&r, &hit, size)?;
        prop_assert!(
            on_sphere(hit.point.to_f64()) <= S::OFF_SURFACE * size,
            "{}: hit {} off the sphere",
            S::NAME,
            on_sphere(hit.point.to_f64())
        );
        // Leaving outwards (the mirror direction) does not come back to the sphere.
        let d = r.dir.to_f64();
        let n = hit.normal.to_f64();
        let out = d - n * (2.0 * d.dot(n));
        if out.dot(n) > 1e-3 {
            let leaving = Ray::new(hit.point, Vec3::<S>::from_f64(out.arr()));
            prop_assert_eq!(sphere.hit(&leaving), None, "{} re-hit", S::NAME);
        }
    }
    // Aimed at the centre from outside: a hit, at the distance to the surface.
    let b = Vec3::from_array(base);
    let distance = (c - b).length_f64();
    if distance > radius * 1.01 + 1e-3
        && let Some(r) = ray::<S>(base, (c - b).arr())
    {
        let hit = sphere.hit(&r);
        prop_assert!(hit.is_some(), "{}: aimed at the centre, missed", S::NAME);
        if let Some(hit) = hit {
            let t = hit.t.to_f64();
            prop_assert!(
                (t - (distance - radius)).abs() <= S::OFF_SURFACE * size * 4.0,
                "{}: t = {t}, expected {}",
                S::NAME,
                distance - radius
            );
        }
    }
    Ok(())
}

fn plane_case<S: Bounds>(
    normal: [f64; 3],
    on: [f64; 3],
    base: [f64; 3],
    dir: [f64; 3],
) -> Result<(), TestCaseError> {
    let Some(plane) = object::<S>(ObjectDef::plane("p", "m", normal, on)) else {
        return Ok(());
    };
    let Some(r) = ray::<S>(base, dir) else {
        return Ok(());
    };
    let size = size(&[on, base], 0.0);
    let Some(hit) = plane.hit(&r) else {
        return Ok(());
    };
    check_hit(&r, &hit, size)?;
    let n = Vec3::from_array(normal);
    let n = n * (1.0 / n.length_f64());
    let off = (hit.point.to_f64() - Vec3::from_array(on)).dot(n).abs();
    // The point is computed along the ray, so its error grows with t: a grazing ray's t is
    // off by (rounding of n . dir) / cos, which puts the point off the plane by t times the
    // rounding, whatever the angle.
    let allowed = S::OFF_SURFACE * (size + hit.t.to_f64());
    prop_assert!(
        off <= allowed,
        "{}: hit {off} off the plane (allowed {allowed}, t = {})",
        S::NAME,
        hit.t.to_f64()
    );
    let cos = r.dir.to_f64().dot(n).abs();
    // Leaving through the plane (the ray continued) or off it (mirrored): either no hit,
    // or a hit within rounding of the point itself, which the tracer ignores by skipping
    // the object a ray leaves.
    let d = r.dir.to_f64();
    let mirrored = d - n * (2.0 * d.dot(n));
    for leaving_dir in [d, mirrored] {
        let leaving = Ray::new(hit.point, Vec3::<S>::from_f64(leaving_dir.arr()));
        if let Some(again) = plane.hit(&leaving) {
            // How far from the plane the point was that the ray came back to it from.
            let back = again.t.to_f64() * cos;
            prop_assert!(
                back <= allowed,
                "{}: left the plane and came back {back} later (allowed {allowed})",
                S::NAME
            );
        }
    }
    Ok(())
}

fn rect_case<S: Bounds>(
    on: [f64; 3],
    dims: [f64; 2],
    base: [f64; 3],
    dir: [f64; 3],
) -> Result<(), TestCaseError> {
    let def = RectDef::new([0.0, 1.0, 1.0], on, [1.0, 0.0, 0.0], dims);
    let Some(rect) = object::<S>(ObjectDef::fplane("f", "m", def)) else {
        return Ok(());
    };
    let Some(r) = ray::<S>(base, dir) else {
        return Ok(());
    };
    if let Some(hit) = rect.hit(&r) {
        check_hit(&r, &hit, size(&[on, base], dims[0] + dims[1]))?;
    }
    Ok(())
}

/// Any finite values at all: loading may refuse them, but nothing panics (overflow checks
/// are on in tests) and no hit holds a NaN.
fn no_nan<S: Scalar>(values: [f64; 10]) -> Result<(), TestCaseError> {
    let [a, b, c, d, e, f, g, h, i, j] = values;
    let defs = [
        ObjectDef::sphere("s", "m", [a, b, c], d.abs()),
        ObjectDef::plane("p", "m", [a, b, c], [d, e, f]),
        ObjectDef::fplane(
            "f",
            "m",
            RectDef::new([a, b, c], [d, e, f], [g, h, i], [j.abs(), d.abs()]),
        ),
    ];
    for def in defs {
        let Ok(scene) =
            Scene::<'_, S, 1, 1, 0, 0, 8>::from_defs(&CAMERA, &MATERIALS, &[], &[], &[def])
        else {
            continue;
        };
        let object = &scene.objects()[0];
        let base = Vec3::<S>::from_f64([g, h, i]);
        for dir in [[e, f, g], [j, a, b], [1.0, 0.0, 0.0]] {
            let Some(dir) = Vec3::<S>::from_f64(dir).unit() else {
                continue;
            };
            if let Some(hit) = object.hit(&Ray::new(base, dir)) {
                let all = [hit.t.to_f64()]
                    .into_iter()
                    .chain(hit.point.to_f64().arr())
                    .chain(hit.normal.to_f64().arr());
                for v in all {
                    prop_assert!(!v.is_nan(), "{}: NaN in {hit:?}", S::NAME);
                }
            }
        }
    }
    Ok(())
}

fn any_finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>().prop_filter("finite", |v| v.is_finite()),
        -100.0f64..100.0,
        Just(0.0),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn sphere_hits(center in point(), radius in 0.05f64..20.0, base in point(), dir in direction()) {
        sphere_case::<f64>(center, radius, base, dir)?;
        sphere_case::<f32>(center, radius, base, dir)?;
        sphere_case::<I16F16>(center, radius, base, dir)?;
    }

    #[test]
    fn plane_hits(normal in direction(), on in point(), base in point(), dir in direction()) {
        plane_case::<f64>(normal, on, base, dir)?;
        plane_case::<f32>(normal, on, base, dir)?;
        plane_case::<I16F16>(normal, on, base, dir)?;
    }

    #[test]
    fn rect_hits(on in point(), w in 0.1f64..30.0, h in 0.1f64..30.0, base in point(), dir in direction()) {
        rect_case::<f64>(on, [w, h], base, dir)?;
        rect_case::<f32>(on, [w, h], base, dir)?;
        rect_case::<I16F16>(on, [w, h], base, dir)?;
    }

    #[test]
    fn no_finite_input_gives_nan_or_panics(values in prop::array::uniform10(any_finite())) {
        no_nan::<f64>(values)?;
        no_nan::<f32>(values)?;
        no_nan::<I16F16>(values)?;
    }
}
