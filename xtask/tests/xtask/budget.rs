use kernel_gen::catalog::GeneratedFile;
use xtask::budget::*;

fn file(name: &str, contents: &str, op_counts: &[(&str, usize)]) -> GeneratedFile {
    GeneratedFile {
        name: name.into(),
        contents: contents.into(),
        op_counts: op_counts.iter().map(|(k, n)| (k.to_string(), *n)).collect(),
    }
}

/// A file over the budget is named with its kernels, largest first, their counts
/// and sizes; files within it pass.
#[test]
fn a_file_over_the_budget_names_its_kernels() {
    let small = "pub fn c_self() {\n}\n";
    let large = "pub fn c_pair() {\n    let t0 = 1.0;\n}\npub fn c_pair_lanes() {\n    let t0 = 1.0;\n    let t1 = 2.0;\n}\n";
    let files = [
        file("small.rs", small, &[("c_self", 3)]),
        file(
            "c.rs",
            large,
            &[
                ("c_pair", 70),
                ("c_pair (far field)", 20),
                ("c_pair_lanes (fma)", 50),
            ],
        ),
    ];
    check(&files, large.len()).unwrap();
    let err = check(&files, large.len() - 1).unwrap_err().to_string();
    let c = err.lines().find(|l| l.starts_with("c.rs ")).unwrap();
    assert!(c.ends_with(&format!(" {} bytes", large.len())), "{err}");
    assert!(!err.contains("small.rs"), "{err}");
    let lanes = err.find("c_pair_lanes ").unwrap();
    let pair = err.find("c_pair ").unwrap();
    assert!(lanes < pair, "largest first: {err}");
    assert!(err.contains("70 flops, 20 flops (far field)"), "{err}");
    assert!(err.contains("50 flops (fma)"), "{err}");
    assert!(err.contains("Green::image_terms"), "{err}");
    // a file of many functions: the largest LISTED of them
    let many: String = (0..LISTED + 2)
        .map(|k| format!("pub fn f{k}() {{\n{}}}\n", "    x;\n".repeat(k)))
        .collect();
    let err = check(&[file("many.rs", &many, &[])], 0)
        .unwrap_err()
        .to_string();
    assert!(err.contains(&format!("  f{} ", LISTED + 1)), "{err}");
    assert!(!err.contains("  f1 "), "{err}");
    assert!(err.contains("  (2 smaller functions)"), "{err}");
}
