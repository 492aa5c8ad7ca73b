//! A 32x32 blue-noise threshold matrix (1,024 bytes of flash).
//!
//! Made by Ulichney's void-and-cluster method (1993) on the torus, with a Gaussian filter of
//! sigma 1.5 pixels: a 10 % random start (a fixed xorshift seed) relaxed by moving its
//! tightest cluster to its largest void until stable; ranks below its count by removing
//! tightest clusters, above by filling largest voids (past half, the tightest clusters of
//! the empty cells). Ties go to the lowest index. Each of the 1,024 ranks is stored divided
//! by four, so each of 256 thresholds covers four cells, spread as the ranks are. The test
//! below regenerates the table and compares it entry by entry.

/// The matrix: rank divided by four, rows by `y`.
pub(crate) const BLUE_NOISE: [[u8; 32]; 32] = include!("blue_noise.table");

#[cfg(test)]
pub(crate) mod generate {
    /// The side of the matrix.
    const SIDE: usize = 32;
    const CELLS: usize = SIDE * SIDE;

    /// The Gaussian weight of each offset on the torus.
    fn kernel() -> Vec<f64> {
        let mut k = vec![0.0; CELLS];
        for dy in 0..SIDE {
            for dx in 0..SIDE {
                let wrap = |d: usize| d.min(SIDE - d) as f64;
                let r2 = wrap(dx).powi(2) + wrap(dy).powi(2);
                k[dy * SIDE + dx] = (-r2 / (2.0 * 1.5 * 1.5)).exp();
            }
        }
        k
    }

    /// Each cell's filtered density of the cells where `pattern` is `on`.
    struct Field {
        kernel: Vec<f64>,
        energy: Vec<f64>,
    }

    impl Field {
        fn new(pattern: &[bool], on: bool) -> Self {
            let mut f = Field {
                kernel: kernel(),
                energy: vec![0.0; CELLS],
            };
            for (i, &p) in pattern.iter().enumerate() {
                if p == on {
                    f.add(i, 1.0);
                }
            }
            f
        }

        fn add(&mut self, at: usize, sign: f64) {
            let (ax, ay) = (at % SIDE, at / SIDE);
            for y in 0..SIDE {
                for x in 0..SIDE {
                    let d = ((y + SIDE - ay) % SIDE) * SIDE + (x + SIDE - ax) % SIDE;
                    self.energy[y * SIDE + x] += sign * self.kernel[d];
                }
            }
        }

        /// The cell with `pattern == on` of the highest energy (`highest`) or the lowest.
        fn extreme(&self, pattern: &[bool], on: bool, highest: bool) -> usize {
            let mut best = usize::MAX;
            for (i, &p) in pattern.iter().enumerate() {
                if p != on {
                    continue;
                }
                let better = best == usize::MAX
                    || (highest && self.energy[i] > self.energy[best])
                    || (!highest && self.energy[i] < self.energy[best]);
                if better {
                    best = i;
                }
            }
            best
        }
    }

    /// The ranks 0..1024 of every cell.
    pub(crate) fn ranks() -> Vec<usize> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut pattern = vec![false; CELLS];
        let start = CELLS / 10;
        let mut placed = 0;
        while placed < start {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let i = (state % CELLS as u64) as usize;
            if !pattern[i] {
                pattern[i] = true;
                placed += 1;
            }
        }
        // Relax: the tightest cluster to the largest void, until it would move back.
        let mut ones = Field::new(&pattern, true);
        loop {
            let cluster = ones.extreme(&pattern, true, true);
            pattern[cluster] = false;
            ones.add(cluster, -1.0);
            let void = ones.extreme(&pattern, false, false);
            pattern[void] = true;
            ones.add(void, 1.0);
            if void == cluster {
                break;
            }
        }
        let mut rank = vec![0; CELLS];
        // Below the start: remove tightest clusters.
        {
            let mut p = pattern.clone();
            let mut f = Field::new(&p, true);
            for r in (0..start).rev() {
                let c = f.extreme(&p, true, true);
                p[c] = false;
                f.add(c, -1.0);
                rank[c] = r;
            }
        }
        // Up to half: fill largest voids.
        let mut f = Field::new(&pattern, true);
        for r in start..CELLS / 2 {
            let v = f.extreme(&pattern, false, false);
            pattern[v] = true;
            f.add(v, 1.0);
            rank[v] = r;
        }
        // Past half: fill the tightest clusters of the empty cells.
        let mut empty = Field::new(&pattern, false);
        for r in CELLS / 2..CELLS {
            let c = empty.extreme(&pattern, false, true);
            pattern[c] = true;
            empty.add(c, -1.0);
            rank[c] = r;
        }
        rank
    }

    #[test]
    fn the_table_is_void_and_cluster() {
        let ranks = ranks();
        let mut seen = vec![false; CELLS];
        for &r in &ranks {
            assert!(!seen[r]);
            seen[r] = true;
        }
        for (y, row) in super::BLUE_NOISE.iter().enumerate() {
            for (x, &stored) in row.iter().enumerate() {
                assert_eq!(usize::from(stored), ranks[y * SIDE + x] / 4, "{x} {y}");
            }
        }
    }

    /// Prints the table (run with `--ignored --nocapture` to regenerate it).
    #[test]
    #[ignore = "prints src/dither/blue_noise.table"]
    fn print_table() {
        let ranks = ranks();
        let mut out = String::from("[\n");
        for y in 0..SIDE {
            let row: Vec<String> = (0..SIDE)
                .map(|x| (ranks[y * SIDE + x] / 4).to_string())
                .collect();
            out += &format!("    [{}],\n", row.join(", "));
        }
        out += "]\n";
        std::fs::write("src/dither/blue_noise.table", out).unwrap();
    }
}
