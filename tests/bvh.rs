//! The bounding-volume hierarchy decides only which objects a ray is tested against, never
//! what a test answers: for random scenes of spheres and rectangles (duplicates included, so
//! that ties happen) and random rays, the closest hit and the shadow test through the tree
//! are the ones every object tested in order gives, in every number type, with the shadow
//! cache or without.

use microray::bvh::{Bvh, MIN_OBJECTS};
use microray::hits::{Among, any_hit_among, any_hit_remembering, closest_hit_among};
use microray::object::{ObjectDef, RectDef};
use microray::scalar::I16F16;
use microray::{CameraDef, MaterialDef, Ray, Scalar, Scene, Vec3};
use proptest::prelude::*;
use std::sync::atomic::{AtomicU16, Ordering};

const CAMERA: CameraDef<'static> = CameraDef::new("c", [8, 6], [8.0, 6.0], [4.0, 3.0, 6.0]);
const MATERIALS: [MaterialDef<'static>; 1] = [MaterialDef::new("m")];
type Big<'t, S> = Scene<'t, S, 256, 1, 0, 0, 8>;

#[derive(Clone, Debug)]
struct Shape {
    center: [f64; 3],
    size: f64,
    rect: bool,
}

fn shape() -> impl Strategy<Value = Shape> {
    (
        [-20.0f64..20.0, -20.0f64..20.0, -40.0f64..0.0],
        0.05f64..4.0,
        prop::bool::weighted(0.2),
    )
        .prop_map(|(center, size, rect)| Shape { center, size, rect })
}

fn scene<S: Scalar>(shapes: &[Shape]) -> Option<Big<'static, S>> {
    let names: Vec<String> = (0..shapes.len()).map(|i| format!("o{i}")).collect();
    let defs: Vec<ObjectDef<'_>> = shapes
        .iter()
        .zip(&names)
        .map(|(s, name)| {
            if s.rect {
                let [x, y, z] = s.center;
                ObjectDef::fplane(
                    name,
                    "m",
                    RectDef::new(
                        [0.3, 1.0, 0.2],
                        [x, y, z],
                        [1.0, 0.0, 0.0],
                        [s.size, s.size],
                    ),
                )
            } else {
                ObjectDef::sphere(name, "m", s.center, s.size)
            }
        })
        .chain([ObjectDef::plane(
            "floor",
            "m",
            [0.0, 1.0, 0.0],
            [0.0, -25.0, 0.0],
        )])
        .collect();
    let scene = Scene::from_defs(&CAMERA, &MATERIALS, &[], &[], &defs).ok()?;
    // Leak the names' borrow: the scene owns copies of them.
    drop(defs);
    Some(scene)
}

fn check<S: Scalar>(shapes: &[Shape], rays: &[([f64; 3], [f64; 3])]) -> Result<(), TestCaseError> {
    let Some(scene) = scene::<S>(shapes) else {
        return Ok(());
    };
    let objects = scene.objects();
    let kept: Vec<u16> = (0..objects.len() as u16).collect();
    let bvh: Bvh<S, 256> = Bvh::new(objects, &kept, scene.camera().viewpoint());
    if shapes.len() >= MIN_OBJECTS {
        prop_assert!(bvh.nodes() > 0 && bvh.nodes() < 2 * objects.len());
    }
    let Some(tree) = bvh.tree() else {
        return Ok(());
    };
    let z = scene.z_limit();
    for (base, dir) in rays {
        let Some(dir) = Vec3::<S>::from_f64(*dir).unit() else {
            continue;
        };
        for ray in [
            Ray::with_length(Vec3::from_f64(*base), dir, S::ONE),
            // An unnormalised ray of unknown length, as f32 and Q16.16 make them.
            Ray::new(Vec3::from_f64(*base), dir * S::TWO),
        ] {
            let all = closest_hit_among(objects, &Among::All, &ray, None, S::UNBOUNDED, z);
            let walked =
                closest_hit_among(objects, &Among::Tree(tree), &ray, None, S::UNBOUNDED, z);
            prop_assert_eq!(walked, all, "{}: closest hit from {:?}", S::NAME, base);
            if let Some((index, t)) = all {
                // The same shadow test, skipping the object hit, up to the hit.
                let skip = (index + 1) % objects.len();
                let limit = t * S::TWO;
                let a = any_hit_among(objects, &Among::All, &ray, skip, limit, z);
                let b = any_hit_among(objects, &Among::Tree(tree), &ray, skip, limit, z);
                prop_assert_eq!(a, b, "{}: shadow test", S::NAME);
                // The shadow cache changes no answer, whatever it remembers: nothing, the
                // object hit (a blocker), the one skipped, or another.
                for remembered in [u16::MAX, index as u16, skip as u16, 0] {
                    let last = AtomicU16::new(remembered);
                    let tree = Among::Tree(tree);
                    let c = any_hit_remembering(objects, &tree, &ray, skip, limit, z, Some(&last));
                    prop_assert_eq!(c, a, "{}: shadow test remembering {}", S::NAME, remembered);
                    // What it remembers now blocks this ray, or nothing blocked it.
                    let now = last.load(Ordering::Relaxed);
                    if now != remembered {
                        prop_assert_eq!(now != u16::MAX, a);
                    }
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn tree_searches_equal_searches_in_order(
        mut shapes in prop::collection::vec(shape(), 1..120),
        duplicates in 0usize..6,
        rays in prop::collection::vec(([-30.0f64..30.0, -30.0f64..30.0, -10.0f64..10.0], [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]), 40),
    ) {
        // Exact copies of some shapes: their hits tie, and the first defined must win.
        for i in 0..duplicates.min(shapes.len()) {
            let copy = shapes[i].clone();
            shapes.push(copy);
        }
        check::<f64>(&shapes, &rays)?;
        check::<f32>(&shapes, &rays)?;
        check::<I16F16>(&shapes, &rays)?;
    }
}
