//! What every subcommand's tests share: a scratch directory, running the binary,
//! assertions on its outcome, the three spheres above a wall and their forces, the
//! library's results to compare with, and readers of the outputs.

use nalgebra::DMatrix;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use stokesian::{Confinement, Moments, Particle, System};

/// A fresh directory under the system's temporary directory, removed on drop.
pub struct Dir(PathBuf);

impl Dir {
    pub fn new(name: &str) -> Dir {
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let k = COUNT.fetch_add(1, Ordering::SeqCst);
        let path =
            std::env::temp_dir().join(format!("stokesian-cli-{}-{k}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&path);
        fs::create_dir_all(&path).expect("create temporary directory");
        Dir(path)
    }

    pub fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        fs::write(&p, text).expect("write input file");
        p
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// File names in the directory, sorted.
    pub fn listing(&self) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(&self.0)
            .expect("read temporary directory")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

pub fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stokesian"))
        .args(args)
        .output()
        .expect("run the stokesian binary")
}

pub fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn assert_ok(o: &Output) {
    assert!(o.status.success(), "command failed: {}", stderr(o));
}

/// The command failed, its message contains every `needle`, and the directory holds
/// exactly the input files (no output, no temporary file).
pub fn assert_fails(o: &Output, needles: &[&str], dir: &Dir, inputs: &[&str]) {
    assert!(!o.status.success(), "command must fail");
    assert_ne!(o.status.code(), Some(101), "the command panicked");
    let msg = stderr(o);
    assert!(!msg.contains("panicked"), "the command panicked: {msg}");
    for n in needles {
        assert!(msg.contains(n), "stderr {msg:?} does not contain {n:?}");
    }
    let mut expected: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(dir.listing(), expected, "files left behind");
}

/// Three spheres of unequal radii above a wall at z = 0.25.
pub const PARTICLES: &str = "x,y,z,radius\n0,0,1.5,1\n2.5,0.5,1.75,1\n-0.5,2.75,2.5,1.2\n";
pub const FORCES: &str =
    "fx,fy,fz,tx,ty,tz\n1,0.5,-0.25,0,0.1,0\n0,1,0.3,-0.2,0,1\n-0.4,0,-1,1,0.5,0\n";

pub fn particles() -> Vec<Particle> {
    vec![
        Particle {
            x: [0.0, 0.0, 1.5],
            a: 1.0,
        },
        Particle {
            x: [2.5, 0.5, 1.75],
            a: 1.0,
        },
        Particle {
            x: [-0.5, 2.75, 2.5],
            a: 1.2,
        },
    ]
}

pub fn forces() -> [[f64; 6]; 3] {
    [
        [1.0, 0.5, -0.25, 0.0, 0.1, 0.0],
        [0.0, 1.0, 0.3, -0.2, 0.0, 1.0],
        [-0.4, 0.0, -1.0, 1.0, 0.5, 0.0],
    ]
}

pub const ETA: f64 = 0.7;
pub const WALL: Confinement = Confinement::Wall { height: 0.25 };

pub fn system(conf: Confinement) -> System {
    System::new(conf, ETA, particles(), false).expect("valid system")
}

pub fn moments_name(m: Moments) -> &'static str {
    match m {
        Moments::F => "F",
        Moments::FT => "FT",
        Moments::FTS => "FTS",
    }
}

/// An NPY v1.0 file of little-endian float64, its header checked: the shape, whether
/// it is in Fortran order, and the values as stored.
pub fn read_npy_values(path: &Path) -> (Vec<usize>, bool, Vec<f64>) {
    let bytes = fs::read(path).expect("read npy");
    assert_eq!(&bytes[..6], b"\x93NUMPY", "magic");
    assert_eq!(&bytes[6..8], &[1, 0], "version 1.0");
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!(
        (10 + hlen) % 64,
        0,
        "header padded to a multiple of 64 bytes"
    );
    let header = std::str::from_utf8(&bytes[10..10 + hlen]).expect("ascii header");
    assert!(header.ends_with('\n'), "header ends with a newline");
    assert!(header.contains("'descr': '<f8'"), "{header}");
    let fortran = header.contains("'fortran_order': True");
    assert!(
        fortran || header.contains("'fortran_order': False"),
        "{header}"
    );
    let shape = header
        .split("'shape': (")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .expect("shape");
    let dims: Vec<usize> = shape
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().expect("shape entry"))
        .collect();
    let data = &bytes[10 + hlen..];
    assert_eq!(
        data.len(),
        8 * dims.iter().product::<usize>(),
        "data length"
    );
    let values = data
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect();
    (dims, fortran, values)
}

/// A matrix from an NPY file (2-D, C or Fortran order).
pub fn read_npy(path: &Path) -> DMatrix<f64> {
    let (dims, fortran, values) = read_npy_values(path);
    assert_eq!(dims.len(), 2, "2-D array");
    let (r, c) = (dims[0], dims[1]);
    if fortran {
        DMatrix::from_column_slice(r, c, &values)
    } else {
        DMatrix::from_row_slice(r, c, &values)
    }
}

/// A matrix written as CSV: one row per line, no header.
pub fn read_csv_matrix(path: &Path) -> DMatrix<f64> {
    let text = fs::read_to_string(path).expect("read csv");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split(',').map(|f| f.parse().expect("number")).collect())
        .collect();
    let c = rows[0].len();
    assert!(rows.iter().all(|r| r.len() == c), "rows of one length");
    DMatrix::from_row_iterator(rows.len(), c, rows.into_iter().flatten())
}

pub fn read_json(path: &Path) -> (serde_json::Value, DMatrix<f64>) {
    let text = fs::read_to_string(path).expect("read json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let rows = v["matrix"].as_array().expect("matrix is an array");
    let r = rows.len();
    let mut values = Vec::new();
    for row in rows {
        let row = row.as_array().expect("row is an array");
        assert_eq!(row.len(), r, "square matrix");
        values.extend(row.iter().map(|x| x.as_f64().expect("number")));
    }
    (v.clone(), DMatrix::from_row_slice(r, r, &values))
}

pub fn assert_bit_equal(got: &DMatrix<f64>, want: &DMatrix<f64>, what: &str) {
    assert_eq!(got.shape(), want.shape(), "{what}: shape");
    for (i, (g, w)) in got.iter().zip(want.iter()).enumerate() {
        assert_eq!(
            g.to_bits(),
            w.to_bits(),
            "{what}: entry {i}: {g:?} != {w:?}"
        );
    }
}

pub fn read_csv(path: &Path, header: &str) -> Vec<Vec<f64>> {
    let text = fs::read_to_string(path).expect("read csv");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(header));
    lines
        .map(|l| l.split(',').map(|f| f.parse().expect("number")).collect())
        .collect()
}

/// Moment-major forces (and torques) for `k` = 3 or 6 columns.
pub fn force_vector(k: usize) -> Vec<f64> {
    let f = forces();
    let n = f.len();
    let mut x = vec![0.0; k * n];
    for a in 0..n {
        for i in 0..3 {
            x[3 * a + i] = f[a][i];
            if k == 6 {
                x[3 * n + 3 * a + i] = f[a][3 + i];
            }
        }
    }
    x
}

/// CLI velocities back in moment-major order.
pub fn velocity_vector(rows: &[Vec<f64>]) -> Vec<f64> {
    let n = rows.len();
    let k = rows[0].len();
    let mut u = vec![0.0; k * n];
    for (a, r) in rows.iter().enumerate() {
        for i in 0..3 {
            u[3 * a + i] = r[i];
            if k == 6 {
                u[3 * n + 3 * a + i] = r[3 + i];
            }
        }
    }
    u
}

pub fn rel_err(got: &[f64], want: &[f64]) -> f64 {
    let d = got
        .iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs())
        .fold(0.0, f64::max);
    d / want.iter().map(|w| w.abs()).fold(0.0, f64::max)
}

/// The options docs/cli.md names as aliases of `--param NAME=`: (option, parameter).
pub const ALIASES: [(&str, &str); 3] = [
    ("--boundary-height", "height"),
    ("--lambda", "lambda"),
    ("--gap", "gap"),
];

pub const SYSTEM_ARGS: [&str; 6] = [
    "--confinement",
    "wall",
    "--boundary-height",
    "0.25",
    "--viscosity",
    "0.7",
];

/// Run `mobility` on a particles file with `extra` options; the output would be M.npy.
pub fn mobility_fails(dir: &Dir, particles: &str, extra: &[&str]) -> Output {
    let p = dir.file("particles.csv", particles);
    let out = dir.path("M.npy");
    run_mobility("wall", "FTS", &p, &out, extra)
}

/// Run `mobility --confinement CONFINEMENT --moments MOMENTS` on `particles`, writing
/// `out`, with `extra` options.
pub fn run_mobility(
    confinement: &str,
    moments: &str,
    particles: &Path,
    out: &Path,
    extra: &[&str],
) -> Output {
    let mut args = vec![
        "mobility",
        "--confinement",
        confinement,
        "--moments",
        moments,
        "--particles",
        s(particles),
        "--out",
        s(out),
    ];
    args.extend(extra);
    run(&args)
}
