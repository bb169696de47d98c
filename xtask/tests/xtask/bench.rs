use kernels::lanes::Isa;
use xtask::bench::*;

#[test]
fn times_have_three_significant_digits_and_a_unit() {
    assert_eq!(format_time(5.349), "5.35 ns");
    assert_eq!(format_time(12.71), "12.7 ns");
    assert_eq!(format_time(611.2), "611 ns");
    assert_eq!(format_time(1110.0), "1.11 us");
    assert_eq!(format_time(8.7e7), "87.0 ms");
    assert_eq!(format_time(2.5e9), "2.50 s");
}

#[test]
fn the_filter_matches_the_ids_literally() {
    assert_eq!(
        escape("wall product M x/F/10000"),
        "wall product M x/F/10000"
    );
    assert_eq!(escape("a.b (c)|d"), r"a\.b \(c\)\|d");
    // 6 pair rows of 3 columns, and the whole operations
    assert_eq!(all_ids(Isa::Avx2).len(), 18 + OPERATION_ROWS.len());
}

#[test]
fn only_the_text_between_the_markers_is_replaced() {
    let dir = std::env::temp_dir().join(format!("xtask-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("page.md");
    std::fs::write(&path, format!("top\n{BEGIN}\nold\n{END}\nbottom\n")).unwrap();
    rewrite(&path, "new\n").unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, format!("top\n{BEGIN}\nnew\n{END}\nbottom\n"));
    std::fs::write(&path, "no markers\n").unwrap();
    assert!(rewrite(&path, "new\n").is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}
