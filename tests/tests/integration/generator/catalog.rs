use kernel_gen::catalog::GeneratedFile;

/// A function's size runs from `pub fn` to its closing brace in column 0; the
/// braces of its body and of other items do not end it early.
#[test]
fn functions_are_measured_from_pub_fn_to_the_closing_brace() {
    let one = "pub fn a_b(x: f64) -> f64 {\n    if x > 0.0 {\n        x\n    } else {\n        -x\n    }\n}\n";
    let two = "pub fn lanes<L: Lane>() {\n}\n";
    let contents = format!(
        "//! doc\nuse crate::x;\n/// doc\n#[inline]\n{one}pub struct S {{\n    a: f64,\n}}\n{two}"
    );
    let f = GeneratedFile {
        name: "f.rs".into(),
        contents,
        op_counts: Vec::new(),
    };
    assert_eq!(f.functions(), [("a_b", one.len()), ("lanes", two.len())]);
}
