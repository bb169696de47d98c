use kernel_gen::catalog::{scene_file, Scene};
use kernel_gen::physics::green::wall::Wall;

/// A standalone scene module defines its own return types and parses as Rust;
/// an F-only scene has no torque, rotation or stresslet code at all.
#[test]
fn standalone_scene_is_self_contained_and_pruned() {
    let text = "name = \"w\"\nconfinement = \"wall\"\nmoments = \"F\"\nradii = \"equal\"\noutputs = [\"dense\", \"product\"]\n";
    let scene = Scene::parse("w.toml", text, &["wall"]).unwrap();
    let f = scene_file(&Wall, &scene, true);
    let parsed: syn::File = syn::parse_str(&f.contents).expect("valid Rust");
    let structs: Vec<String> = parsed
        .items
        .iter()
        .filter_map(|i| match i {
            syn::Item::Struct(s) => Some(s.ident.to_string()),
            _ => None,
        })
        .collect();
    assert_eq!(structs, ["BlocksF", "Product"]);
    assert!(!f.contents.contains("crate::"));
    for absent in ["ul:", "of:", "os:", "es:"] {
        assert!(!f.contents.contains(absent), "{absent} in an F-only scene");
    }
    let names: Vec<&str> = f.op_counts.iter().map(|(n, _)| n.as_str()).collect();
    // the wall's pair kernels also have a lateral far-field branch (`farfield`),
    // its self kernels a closed-form branch (`self_image`)
    assert_eq!(
        names,
        [
            "w_self",
            "w_self (closed form)",
            "w_pair_equal",
            "w_pair_equal (far field)",
            "w_pair_equal_product",
            "w_pair_equal_product (far field)"
        ]
    );
}
