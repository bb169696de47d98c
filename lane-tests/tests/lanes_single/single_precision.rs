//! The single-precision product (`Precision::Single`: `f32` lanes in units where the
//! largest radius, the viscosity and the largest moment are 1) and the change of units
//! it rests on (`Confinement::in_units`, generated for every Green's function from the
//! dimensions of its parameters).

use integration_tests::{all_confinements, blocks, random_spheres};
use kernels::{pair, self_mobility, Confinement};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::{Isa, Moments, Particle, Precision, System};

/// Length dimension of each block `(name, 1 + p + q)`: the moment's `p` (force 0;
/// torque, stresslet 1) plus the response's `q` (velocity 0; rotation, strain 1).
const POWERS: [(&str, i32); 9] = [
    ("uf", 1),
    ("ul", 2),
    ("us", 2),
    ("of", 2),
    ("ol", 3),
    ("os", 3),
    ("ef", 2),
    ("el", 3),
    ("es", 3),
];

/// Every block of every confinement's pair and self mobility in other units: measured
/// from another origin in `unit` and with viscosity 1, `M = M' / (eta unit^(1+p+q))`.
/// Tolerance 1e-13 of each block's norm: the kernels' own round-off (about 1e-15,
/// report section a) at two sets of inputs that differ by roundings of the change of
/// units.
#[test]
fn every_block_scales_with_the_units_of_length() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for (name, conf) in all_confinements() {
        let ps = random_spheres(&mut rng, &conf, 2, (0.4, 1.2), 0.05, 6.0);
        let eta = 1.7;
        for (origin, unit) in [([0.5, -1.5, 0.3], 0.37), ([10.0, 3.0, -2.0], 2.5e-6)] {
            let c = conf.in_units(origin, unit);
            let to =
                |x: [f64; 3]| -> [f64; 3] { std::array::from_fn(|k| (x[k] - origin[k]) / unit) };
            let (a, b) = (&ps[0], &ps[1]);
            let cases = [
                (
                    pair(&conf, eta, a.x, a.a, b.x, b.a),
                    pair(&c, 1.0, to(a.x), a.a / unit, to(b.x), b.a / unit),
                ),
                (
                    self_mobility(&conf, eta, a.x, a.a),
                    self_mobility(&c, 1.0, to(a.x), a.a / unit),
                ),
            ];
            for (m, scaled) in cases {
                for ((block, want), ((_, got), (_, k))) in blocks(&m)
                    .into_iter()
                    .zip(blocks(&scaled).into_iter().zip(POWERS))
                {
                    let f = 1.0 / (eta * unit.powi(k));
                    let d: f64 = want
                        .iter()
                        .zip(&got)
                        .map(|(w, g)| (w - g * f).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    let n: f64 = want.iter().map(|w| w * w).sum::<f64>().sqrt();
                    assert!(d <= 1e-13 * n, "{name} {block} (unit {unit}): {:e}", d / n);
                }
            }
        }
    }
}

/// A system in SI units (radii 0.4-1.2 um, water, forces of pN, torques of pN um) far
/// from the origin: lengths 1e-6 and `1 / (eta a^3)` 1e21 would overflow `f32` in the
/// kernels' intermediates without the change of units.
fn si_system(rng: &mut ChaCha8Rng, conf: &Confinement, n: usize) -> (System, Confinement) {
    let um = 1e-6;
    let offset = [3.0e-2, -1.0e-2, 5.0e-3];
    // the confinement moved with the particles: h -> h um + offset
    let si = conf.in_units(offset.map(|o| -o / um), 1.0 / um);
    let ps: Vec<Particle> = random_spheres(rng, conf, n, (0.4, 1.2), 0.05, 40.0)
        .into_iter()
        .map(|p| Particle {
            x: std::array::from_fn(|k| p.x[k] * um + offset[k]),
            a: p.a * um,
        })
        .collect();
    (System::new(si, 1.0e-3, ps, false).unwrap(), si)
}

/// The single-precision product against the double-precision one, every confinement,
/// F and FT, every instruction set, in SI units: within 2e-6 of the norm of each
/// part of the response (velocities; rotations and strains). Per pair the `f32` lanes
/// agree with the `f64` kernels to 2e-6 of the pair's output norm away from the wall's
/// lateral switch (`scalar.rs`, about 2e-6 at worst, the slit); the sums run in `f32` within a tile and in `f64`
/// across tiles, and the errors of many pairs partly cancel (measured 1e-8 to 2e-7). Measured:
/// printed by `-- --nocapture`. FTS asked for in single precision is the double-precision
/// product, bit for bit, on the same instruction set.
#[test]
fn single_precision_product_agrees_with_double_in_any_units() {
    let mut rng = ChaCha8Rng::seed_from_u64(32);
    for (name, conf) in all_confinements() {
        let (s, _) = si_system(&mut rng, &conf, 150);
        let n = s.len();
        for moments in [Moments::F, Moments::FT, Moments::FTS] {
            let k = moments.per_particle();
            // forces of 1 pN; torques and stresslets of 1 pN um
            let x: Vec<f64> = (0..k * n)
                .map(|i| rng.gen_range(-1.0..1.0) * if i < 3 * n { 1e-12 } else { 1e-18 })
                .collect();
            let double = s.apply_with(moments, &x, Isa::Scalar, Precision::Double);
            for isa in Isa::all_available() {
                let single = s.apply_with(moments, &x, isa, Precision::Single);
                if moments == Moments::FTS {
                    let same = s.apply_with(moments, &x, isa, Precision::Double);
                    assert!(single == same, "{name} FTS {isa:?}: not the double product");
                    continue;
                }
                assert!(
                    single.iter().all(|v| v.is_finite()),
                    "{name} {moments:?} {isa:?}"
                );
                for (part, range) in [
                    ("velocities", 0..3 * n),
                    ("rotations and strains", 3 * n..k * n),
                ] {
                    if range.is_empty() {
                        continue;
                    }
                    let d: f64 = range
                        .clone()
                        .map(|i| (single[i] - double[i]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    let m: f64 = range.map(|i| double[i] * double[i]).sum::<f64>().sqrt();
                    println!(
                        "{name:<13} {moments:<3?} {:<7} {part}: {:.1e}",
                        isa.name(),
                        d / m
                    );
                    assert!(
                        d <= 2e-6 * m,
                        "{name} {moments:?} {isa:?} {part}: {:e}",
                        d / m
                    );
                }
            }
        }
    }
}
