use kernel_gen::catalog::{Moments, Scene};

#[test]
fn parses_and_rejects() {
    let ok = "name = \"wall_f\"\nconfinement = \"wall\"\nmoments = \"F\"\nradii = \"equal\"\noutputs = [\"product\"]\n";
    let s = Scene::parse("a.toml", ok, &["wall"]).unwrap();
    assert_eq!(s.moments, Moments::F);
    assert!(s.product && !s.dense);
    let e = Scene::parse("a.toml", &ok.replace("\"F\"", "\"FX\""), &["wall"]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "a.toml: moments = \"FX\": must be F, FT or FTS"
    );
    let e = Scene::parse("a.toml", &ok.replace("wall\"\nm", "moon\"\nm"), &["wall"]).unwrap_err();
    assert!(e.to_string().contains("confinement = \"moon\""), "{e}");
    let e = Scene::parse("a.toml", "name = 3", &["wall"]).unwrap_err();
    assert!(e.to_string().starts_with("a.toml: "), "{e}");
}
