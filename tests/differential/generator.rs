//! A seeded generator of random valid scenes: every object kind and light kind, mirrors,
//! glass and glints, and now and then a nasty case (objects that touch, cut or duplicate
//! each other, a light on a surface or at the eye, a surface through the eye, the eye in a
//! sphere, tiny and huge sizes, far offsets, strong lights, barely transparent mirrors).
//! The same seed gives the same scene on every machine (splitmix64, numbers printed in
//! Rust's shortest round-trip form).

use std::fmt::Write as _;

/// splitmix64: small, seedable, and good enough to spread scenes about.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.unit()
    }

    /// Log-uniform in `[low, high)`.
    fn log_range(&mut self, low: f64, high: f64) -> f64 {
        (low.ln() + (high.ln() - low.ln()) * self.unit()).exp()
    }

    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn rgb(&mut self, high: f64) -> [f64; 3] {
        [
            self.range(0.0, high),
            self.range(0.0, high),
            self.range(0.0, high),
        ]
    }

    /// A direction: along an axis now and then (the course's floors and walls), else any.
    fn direction(&mut self) -> [f64; 3] {
        if self.chance(0.3) {
            let mut v = [0.0; 3];
            v[self.below(3)] = if self.chance(0.5) { 1.0 } else { -1.0 };
            return v;
        }
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if length > 0.2 {
                // Any length: the scene language scales directions itself.
                let k = self.log_range(1e-4, 1e3);
                return [v[0] * k, v[1] * k, v[2] * k];
            }
        }
    }
}

/// A generated scene: its text, its textures' files, and the nasty cases it has.
pub struct Generated {
    pub text: String,
    pub textures: Vec<(String, Vec<u8>)>,
    pub nasty: Vec<&'static str>,
}

impl Generated {
    /// The bytes of a texture file by name (for the parser's texture look-up).
    pub fn texture(&self, name: &str) -> Option<&[u8]> {
        self.textures
            .iter()
            .find(|(file, _)| file == name)
            .map(|(_, bytes)| bytes.as_slice())
    }
}

fn v3(v: [f64; 3]) -> String {
    format!("{} {} {}", v[0], v[1], v[2])
}

/// A `sphere` block.
fn sphere(name: &str, material: &str, center: [f64; 3], radius: f64) -> String {
    format!(
        "sphere {name}\n{{\n  material {material}\n  center {}\n  radius {radius}\n}}\n",
        v3(center)
    )
}

/// A `plane` block.
fn plane(name: &str, material: &str, normal: [f64; 3], point: [f64; 3]) -> String {
    format!(
        "plane {name}\n{{\n  material {material}\n  normal {}\n  point {}\n}}\n",
        v3(normal),
        v3(point)
    )
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let length = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    scale(a, 1.0 / length)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// What the generator knows of the scene so far, for the nasty cases.
struct Layout {
    window: [f64; 2],
    /// The scene's size: the window's width.
    size: f64,
    /// Added to every object's and light's position (a far offset, or none).
    offset: [f64; 3],
    materials: Vec<String>,
    textures: Vec<String>,
    spheres: Vec<([f64; 3], f64)>,
    planes: Vec<([f64; 3], [f64; 3])>,
    blocks: Vec<String>,
}

impl Layout {
    /// A point in view, `near` to `far` sizes behind the window.
    fn point(&self, rng: &mut Rng, near: f64, far: f64) -> [f64; 3] {
        let depth = rng.range(near, far);
        add(
            [
                rng.range(-0.2, 1.2) * self.window[0],
                rng.range(-0.2, 1.2) * self.window[1],
                -depth * self.size,
            ],
            self.offset,
        )
    }

    fn material(&self, rng: &mut Rng) -> String {
        self.materials[rng.below(self.materials.len())].clone()
    }

    /// `normal`, `point`, `xdir`, `dimensions` of a rectangle in view.
    fn rect(&self, rng: &mut Rng) -> String {
        let normal = rng.direction();
        let xdir = loop {
            let x = rng.direction();
            let sine = {
                let c = cross(unit(normal), unit(x));
                (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
            };
            if sine > 0.1 {
                break x;
            }
        };
        let point = self.point(rng, 0.0, 2.0);
        let dimensions = [
            rng.log_range(0.05, 1.5) * self.size,
            rng.log_range(0.05, 1.5) * self.size,
        ];
        format!(
            "  normal {}\n  point {}\n  xdir {}\n  dimensions {} {}\n",
            v3(normal),
            v3(point),
            v3(xdir),
            dimensions[0],
            dimensions[1]
        )
    }
}

/// A tiny binary PPM of random texels.
fn ppm(rng: &mut Rng) -> Vec<u8> {
    let (w, h) = (1 + rng.below(6), 1 + rng.below(6));
    let mut bytes = format!("P6\n{w} {h}\n255\n").into_bytes();
    bytes.extend((0..w * h * 3).map(|_| rng.below(256) as u8));
    bytes
}

/// The scene of `seed`.
pub fn scene(seed: u64) -> Generated {
    let mut rng = Rng::new(seed);
    let rng = &mut rng;
    let mut nasty = Vec::new();
    let mut flag = |rng: &mut Rng, p: f64, name: &'static str| {
        let on = rng.chance(p);
        if on {
            nasty.push(name);
        }
        on
    };
    let size = rng.log_range(0.5, 150.0);
    let window = [size, size * rng.range(0.5, 1.2)];
    let eye = [
        window[0] * rng.range(0.2, 0.8),
        window[1] * rng.range(0.2, 0.8),
        size * rng.log_range(0.3, 3.0),
    ];
    let offset = if flag(rng, 0.05, "far offset") {
        [0.0, 0.0, -size * rng.log_range(10.0, 1e4)]
    } else {
        [0.0; 3]
    };
    let mut text = String::new();
    let pixels = [16 + rng.below(40), 12 + rng.below(30)];
    writeln!(
        text,
        "camera eye\n{{\n  pixeldim {} {}\n  worlddim {} {}\n  viewpoint {}\n}}",
        pixels[0],
        pixels[1],
        window[0],
        window[1],
        v3(eye)
    )
    .unwrap();
    let mut layout = Layout {
        window,
        size,
        offset,
        materials: Vec::new(),
        textures: Vec::new(),
        spheres: Vec::new(),
        planes: Vec::new(),
        blocks: Vec::new(),
    };

    // Materials.
    let barely = flag(rng, 0.05, "barely transparent mirror");
    for m in 0..1 + rng.below(4) {
        let name = format!("m{m}");
        let mut block = format!("material {name}\n{{\n");
        let diffuse = rng.rgb(4.0);
        writeln!(
            block,
            "  ambient {}\n  diffuse {}",
            v3(rng.rgb(1.5)),
            v3(diffuse)
        )
        .unwrap();
        if barely && m == 0 {
            block.push_str("  specular 0.93\n  transparency 0.000001\n");
        } else {
            if rng.chance(0.4) {
                if rng.chance(0.5) {
                    writeln!(block, "  specular {}", rng.range(0.0, 1.0)).unwrap();
                } else {
                    writeln!(block, "  specular {}", v3(rng.rgb(1.0))).unwrap();
                }
            }
            if rng.chance(0.3) {
                writeln!(block, "  shininess {}", rng.log_range(1.0, 200.0)).unwrap();
            }
            if rng.chance(0.3) && diffuse.iter().any(|&d| d > 0.0) {
                writeln!(block, "  transparency {}", rng.range(0.0, 1.0)).unwrap();
            }
        }
        block.push_str("}\n");
        text.push_str(&block);
        layout.materials.push(name);
    }

    // Textures.
    let mut textures = Vec::new();
    for t in 0..rng.below(3) {
        let (name, file) = (format!("t{t}"), format!("t{t}.ppm"));
        writeln!(text, "texture {name}\n{{\n  filename {file}\n}}").unwrap();
        textures.push((file, ppm(rng)));
        layout.textures.push(name);
    }

    // Objects.
    for o in 0..1 + rng.below(7) {
        let material = layout.material(rng);
        let kind = rng.below(if layout.textures.is_empty() { 5 } else { 6 });
        let block = match kind {
            0 => {
                let normal = rng.direction();
                let point = layout.point(rng, 0.0, 2.0);
                layout.planes.push((normal, point));
                plane(&format!("p{o}"), &material, normal, point)
            }
            1 => {
                let center = layout.point(rng, 0.2, 2.0);
                let radius = rng.log_range(0.03, 0.5) * size;
                layout.spheres.push((center, radius));
                sphere(&format!("s{o}"), &material, center, radius)
            }
            2 => format!(
                "fplane f{o}\n{{\n  material {material}\n{}}}\n",
                layout.rect(rng)
            ),
            3 => {
                let alt = layout.material(rng);
                format!(
                    "tiled_plane tp{o}\n{{\n  material {material}\n{}  altmaterial {alt}\n}}\n",
                    layout.rect(rng)
                )
            }
            4 => {
                let base = layout.point(rng, 0.2, 2.0);
                format!(
                    "revsurf r{o}\n{{\n  material {material}\n  surfer {}\n  base {}\n  direction {}\n  height {}\n}}\n",
                    1 + rng.below(3),
                    v3(base),
                    v3(rng.direction()),
                    rng.log_range(0.5, 25.0)
                )
            }
            _ => {
                let texture = layout.textures[rng.below(layout.textures.len())].clone();
                format!(
                    "texplane x{o}\n{{\n  material {material}\n{}  texname {texture}\n  mode {}\n}}\n",
                    layout.rect(rng),
                    rng.below(2)
                )
            }
        };
        layout.blocks.push(block);
    }
    // The nasty objects.
    if let Some(&(center, radius)) = layout.spheres.first() {
        if flag(rng, 0.08, "touching spheres") {
            let d = unit(rng.direction());
            let r = rng.log_range(0.1, 2.0) * radius;
            let c = add(center, scale(d, radius + r));
            layout
                .blocks
                .push(sphere("touching", &layout.material(rng), c, r));
        }
        if flag(rng, 0.08, "intersecting spheres") {
            let c = add(center, scale(unit(rng.direction()), radius * 0.5));
            layout
                .blocks
                .push(sphere("cutting", &layout.material(rng), c, radius));
        }
    }
    if flag(rng, 0.05, "tiny sphere") {
        let c = layout.point(rng, 0.5, 0.5);
        layout
            .blocks
            .push(sphere("tiny", &layout.material(rng), c, size * 1e-4));
    }
    if flag(rng, 0.05, "huge sphere") {
        let r = size * rng.log_range(10.0, 1e3);
        let c = add(layout.point(rng, 1.0, 1.0), [0.0, -r - size, 0.0]);
        layout
            .blocks
            .push(sphere("huge", &layout.material(rng), c, r));
    }
    if !layout.blocks.is_empty() && flag(rng, 0.05, "duplicated object") {
        let copy = layout.blocks[rng.below(layout.blocks.len())].replacen('\n', "_again\n", 1);
        layout.blocks.push(copy);
    }
    if let Some(&(normal, point)) = layout.planes.first()
        && flag(rng, 0.05, "coincident planes")
    {
        // The same plane, its normal scaled and its point moved along it.
        let along = cross(normal, [0.3, 0.5, 0.7]);
        let p = add(point, scale(along, rng.range(-1.0, 1.0)));
        let material = layout.material(rng);
        layout
            .blocks
            .push(plane("same", &material, scale(normal, 2.0), p));
    }
    if flag(rng, 0.05, "plane through the eye") {
        // The material first, then the normal: the order the seeds were drawn in.
        let material = layout.material(rng);
        layout
            .blocks
            .push(plane("through_eye", &material, rng.direction(), eye));
    }
    if flag(rng, 0.05, "eye in a sphere") {
        let r = size * rng.range(0.2, 2.0);
        let c = add(eye, scale(unit(rng.direction()), r * rng.range(0.0, 0.9)));
        layout
            .blocks
            .push(sphere("around_eye", &layout.material(rng), c, r));
    }
    for block in &layout.blocks {
        text.push_str(block);
    }

    // Lights.
    let strong = flag(rng, 0.1, "strong lights");
    for l in 0..1 + rng.below(3) {
        let location = add(
            [
                rng.range(-0.5, 1.5) * window[0],
                rng.range(-0.5, 1.5) * window[1],
                rng.range(-2.0, 1.0) * size,
            ],
            offset,
        );
        let emissivity = if strong {
            rng.rgb(1500.0)
        } else {
            rng.rgb(10.0)
        };
        let common = format!(
            "  location {}\n  emissivity {}\n",
            v3(location),
            v3(emissivity)
        );
        match rng.below(if layout.textures.is_empty() { 2 } else { 3 }) {
            0 => writeln!(text, "light l{l}\n{{\n{common}}}").unwrap(),
            1 => {
                let point = layout.point(rng, 0.0, 2.0);
                writeln!(
                    text,
                    "spotlight l{l}\n{{\n{common}  point {}\n  theta {}\n}}",
                    v3(point),
                    rng.range(2.0, 90.0)
                )
                .unwrap();
            }
            _ => {
                let texture = layout.textures[rng.below(layout.textures.len())].clone();
                writeln!(
                    text,
                    "projector l{l}\n{{\n{common}{}  texname {texture}\n  mode {}\n}}",
                    layout.rect(rng),
                    rng.below(2)
                )
                .unwrap();
            }
        }
    }
    if let Some(&(center, radius)) = layout.spheres.first()
        && flag(rng, 0.05, "light on a sphere")
    {
        let at = add(center, scale(unit(rng.direction()), radius));
        writeln!(
            text,
            "light on_sphere\n{{\n  location {}\n  emissivity {}\n}}",
            v3(at),
            v3(rng.rgb(10.0))
        )
        .unwrap();
    }
    if let Some(&(_, point)) = layout.planes.first()
        && flag(rng, 0.05, "light on a plane")
    {
        writeln!(
            text,
            "light on_plane\n{{\n  location {}\n  emissivity {}\n}}",
            v3(point),
            v3(rng.rgb(10.0))
        )
        .unwrap();
    }
    if flag(rng, 0.05, "light at the eye") {
        writeln!(
            text,
            "light at_eye\n{{\n  location {}\n  emissivity {}\n}}",
            v3(eye),
            v3(rng.rgb(10.0))
        )
        .unwrap();
    }
    Generated {
        text,
        textures,
        nasty,
    }
}
