use kernel_gen::emit::literal;

#[test]
fn literals_round_trip() {
    for c in [1.0 / 3.0, -2.5, 1e-300, 6.02e23, 0.1] {
        let s = literal(c).to_string().replace([' ', '(', ')'], "");
        let back: f64 = s.parse().unwrap();
        assert_eq!(back, c, "{s}");
    }
}
