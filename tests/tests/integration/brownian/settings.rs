//! The settings of a Brownian run: a run is its steps with every `k`-th kept, and every
//! setting out of range is refused by name.

use rand::SeedableRng;
use stokesian::{
    Brownian, BrownianError, ExternalForces, Moments, Noise, Particle, Run, RunTally, Scheme,
    System,
};

fn bd() -> Brownian {
    Brownian {
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: ExternalForces {
            weight: 0.5,
            strength: 0.0,
            debye: 1.0,
            trap: 0.0,
            torque: [0.0; 3],
        },
        noise: Noise::Cholesky,
        hydrodynamics: true,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        lubrication: None,
    }
}

fn system() -> System {
    let p = |x, z| Particle {
        x: [x, 0.0, z],
        a: 1.0,
    };
    System::new(
        kernels::Confinement::Wall { height: 0.0 },
        1.0,
        vec![p(0.0, 2.0), p(3.0, 1.5)],
        false,
    )
    .unwrap()
}

#[test]
fn a_run_is_its_steps_with_every_kth_kept() {
    let run = Run {
        steps: 6,
        every: 3,
        seed: 9,
        max_rejections: 0,
    };
    let mut frames = Vec::new();
    let tally = system()
        .brownian_run(&bd(), &run, |step, s, q| {
            assert_eq!(q, &[[1.0, 0.0, 0.0, 0.0]; 2]);
            frames.push((step, s.particles().to_vec()));
        })
        .unwrap();
    assert_eq!(tally, RunTally::default());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let mut s = system();
    let mut want = vec![(0, s.particles().to_vec())];
    for step in 1..=6 {
        s = s.brownian_step(&bd(), &mut rng, step).unwrap().system;
        if step % 3 == 0 {
            want.push((step, s.particles().to_vec()));
        }
    }
    assert_eq!(frames, want);
}

#[test]
fn settings_out_of_range_are_refused() {
    let run = Run {
        steps: 1,
        every: 1,
        seed: 0,
        max_rejections: 0,
    };
    let refused = |b: Brownian, name: &str| match system().brownian_run(&b, &run, |_, _, _| {}) {
        Err(BrownianError::BadSetting { name: n, .. }) => assert_eq!(n, name),
        other => panic!("{name}: {other:?}"),
    };
    refused(Brownian { dt: 0.0, ..bd() }, "dt");
    refused(
        Brownian {
            kt: f64::NAN,
            ..bd()
        },
        "kt",
    );
    let mut b = bd();
    b.forces.trap = -1.0;
    refused(b, "trap");
    b = bd();
    b.forces.debye = 0.0;
    refused(b, "debye_length");
    b = bd();
    b.noise = Noise::Lanczos { tol: -1.0 };
    refused(b, "lanczos");
    let every0 = Run { every: 0, ..run };
    assert!(matches!(
        system().brownian_run(&bd(), &every0, |_, _, _| {}),
        Err(BrownianError::BadSetting { name: "every", .. })
    ));
    // a step that always crosses the wall: redrawn until the limit
    let heavy = Brownian {
        dt: 10.0,
        forces: ExternalForces {
            weight: 100.0,
            ..bd().forces
        },
        ..bd()
    };
    assert!(matches!(
        system().brownian_run(
            &heavy,
            &Run {
                max_rejections: 3,
                ..run
            },
            |_, _, _| {}
        ),
        Err(BrownianError::TooManyRejections {
            rejections: 4,
            max: 3,
            ..
        })
    ));
}
