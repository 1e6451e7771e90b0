//! How often, and where, the paper's walk evaluated in binary32 / binary64
//! (`uv2index::index_in_f32_arithmetic`, `uv2index::index_in_f64_arithmetic`) differs from the exact
//! walk (`uv2index::exact_index_f32` / `uv2index::exact_index_f64`, cross-checked with
//! `BigRational` for every counterexample printed).
//!
//! Reproduces the tables in `docs/float.md`:
//!
//! ```text
//! cargo run --release --example float_study -- [SAMPLES_PER_CELL] [SEED]
//! ```

use micromap_index::{uv2index, Level};
use micromap_index_test_support::{step_ulps, step_ulps_f64, SplitMix64};
use num_rational::BigRational;

/// Sampling on the crate's `SplitMix64` stream.
struct Rng(SplitMix64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0.below(n)
    }
    /// A real in [0, 1) with 53 random bits.
    fn unit(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The float type under study.
trait Float: Copy {
    const NAME: &'static str;
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    fn bits(self) -> String;
    fn step_ulps(self, ulps: i64) -> Self;
    fn float_walk(u: Self, v: Self, level: Level) -> Result<u64, micromap_index::Error>;
    fn exact_walk(u: Self, v: Self, level: Level) -> Result<u64, micromap_index::Error>;
}

impl Float for f32 {
    const NAME: &'static str = "f32";
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn bits(self) -> String {
        format!("0x{:08x}", self.to_bits())
    }
    fn step_ulps(self, ulps: i64) -> Self {
        step_ulps(self, ulps.clamp(-(1 << 31), (1 << 31) - 1) as i32)
    }
    fn float_walk(u: Self, v: Self, level: Level) -> Result<u64, micromap_index::Error> {
        uv2index::index_in_f32_arithmetic(u, v, level)
    }
    fn exact_walk(u: Self, v: Self, level: Level) -> Result<u64, micromap_index::Error> {
        uv2index::exact_index_f32(u, v, level)
    }
}

impl Float for f64 {
    const NAME: &'static str = "f64";
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn bits(self) -> String {
        format!("0x{:016x}", self.to_bits())
    }
    fn step_ulps(self, ulps: i64) -> Self {
        step_ulps_f64(self, ulps)
    }
    fn float_walk(u: Self, v: Self, level: Level) -> Result<u64, micromap_index::Error> {
        uv2index::index_in_f64_arithmetic(u, v, level)
    }
    fn exact_walk(u: Self, v: Self, level: Level) -> Result<u64, micromap_index::Error> {
        uv2index::exact_index_f64(u, v, level)
    }
}

#[derive(Clone, Copy, Debug)]
enum Class {
    Uniform,
    NearVerticalLine,
    NearHorizontalLine,
    NearDiagonalLine,
    NearVertex,
}

const CLASSES: [Class; 5] = [
    Class::Uniform,
    Class::NearVerticalLine,
    Class::NearHorizontalLine,
    Class::NearDiagonalLine,
    Class::NearVertex,
];

impl Class {
    fn name(self) -> &'static str {
        match self {
            Class::Uniform => "uniform",
            Class::NearVerticalLine => "u = k/2^m ± 0..3 ulp",
            Class::NearHorizontalLine => "v = k/2^m ± 0..3 ulp",
            Class::NearDiagonalLine => "u + v = k/2^m ± 0..3 ulp",
            Class::NearVertex => "vertex ± 0..3 ulp",
        }
    }
}

/// `k / 2^m` for random `m in 1..=level`, `k in 0..=2^m`.
fn lattice_value(rng: &mut Rng, level: u32) -> f64 {
    let m = 1 + rng.below(u64::from(level.max(1))) as u32;
    let k = rng.below((1u64 << m) + 1);
    k as f64 / (1u64 << m) as f64
}

/// A lattice value rounded into `F`, then moved by -3..=3 ulps.
fn near_lattice<F: Float>(rng: &mut Rng, level: u32) -> F {
    let x = F::from_f64(lattice_value(rng, level));
    nudge(rng, x)
}

fn nudge<F: Float>(rng: &mut Rng, x: F) -> F {
    let ulps = rng.below(7) as i64 - 3;
    x.step_ulps(ulps)
}

/// A sample of the class, rounded into the float type, or `None` if it fell
/// outside the triangle.
fn sample<F: Float>(rng: &mut Rng, class: Class, level: u32) -> Option<(F, F)> {
    let (u, v) = match class {
        Class::Uniform => {
            let (u, v) = (rng.unit(), rng.unit());
            if u + v > 1.0 {
                (F::from_f64(1.0 - v), F::from_f64(1.0 - u))
            } else {
                (F::from_f64(u), F::from_f64(v))
            }
        }
        Class::NearVerticalLine => {
            let u = near_lattice::<F>(rng, level);
            (u, F::from_f64(rng.unit() * (1.0 - u.to_f64())))
        }
        Class::NearHorizontalLine => {
            let v = near_lattice::<F>(rng, level);
            (F::from_f64(rng.unit() * (1.0 - v.to_f64())), v)
        }
        Class::NearDiagonalLine => {
            let sum = lattice_value(rng, level);
            let u = F::from_f64(rng.unit() * sum);
            (u, nudge(rng, F::from_f64(sum - u.to_f64())))
        }
        Class::NearVertex => (near_lattice::<F>(rng, level), near_lattice::<F>(rng, level)),
    };
    F::exact_walk(u, v, Level::new(0).unwrap()).ok()?;
    Some((u, v))
}

struct Counterexample {
    level: u32,
    class: Class,
    u: String,
    v: String,
    float: u64,
    exact: u64,
}

fn study<F: Float>(samples: u64, seed: u64, levels: &[u32]) -> Vec<Counterexample> {
    let mut rng = Rng(SplitMix64::new(seed));
    let mut examples = Vec::new();
    println!(
        "\n### uv2index-{} vs exact, {samples} samples per cell\n",
        F::NAME
    );
    print!("| level |");
    for class in CLASSES {
        print!(" {} |", class.name());
    }
    println!("\n|---|{}", "---|".repeat(CLASSES.len()));
    for &level_number in levels {
        let level = Level::new(level_number).unwrap();
        print!("| {level_number} |");
        for class in CLASSES {
            let (mut taken, mut differ) = (0u64, 0u64);
            let mut first = None;
            while taken < samples {
                let Some((u, v)) = sample::<F>(&mut rng, class, level_number) else {
                    continue;
                };
                taken += 1;
                let float = F::float_walk(u, v, level).expect("checked point");
                let exact = F::exact_walk(u, v, level).expect("checked point");
                if float != exact {
                    differ += 1;
                    if first.is_none() {
                        first = Some(Counterexample {
                            level: level_number,
                            class,
                            u: u.bits(),
                            v: v.bits(),
                            float,
                            exact,
                        });
                        // The fixed-point oracle must agree with BigRational.
                        let r = |x: F| BigRational::from_float(x.to_f64()).unwrap();
                        assert_eq!(uv2index::index_real(&r(u), &r(v), level), Ok(exact));
                    }
                }
            }
            print!(
                " {:.4}% ({differ}) |",
                100.0 * differ as f64 / samples as f64
            );
            examples.extend(first);
        }
        println!();
    }
    examples
}

fn main() {
    let mut args = std::env::args().skip(1);
    let samples: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let seed: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(2026);
    let levels = [1, 2, 3, 4, 6, 8, 12, 16, 20, 24, 28, 32];
    println!("seed {seed}; cells: share of samples where the float walk differs (count)");
    let mut examples = study::<f32>(samples, seed, &levels);
    examples.extend(study::<f64>(samples, seed, &levels));
    println!("\n### First counterexample per cell (exact bits)\n");
    println!("| level | class | u | v | float walk | exact walk |");
    println!("|---|---|---|---|---|---|");
    for e in examples {
        println!(
            "| {} | {} | `{}` | `{}` | {} | {} |",
            e.level,
            e.class.name(),
            e.u,
            e.v,
            e.float,
            e.exact
        );
    }
}
