use xtask::report::*;

#[test]
fn civil_date_is_well_formed() {
    let d = today();
    assert_eq!(d.len(), 10);
    assert!(d.starts_with("20"));
}

/// A reduced report into a temporary directory: every file is written and every
/// table has rows.
#[test]
fn reduced_report_writes_files_and_non_empty_tables() {
    let dir = std::env::temp_dir().join(format!("xtask-report-test-{}", std::process::id()));
    let path = run(Config::quick(dir.clone())).expect("the reduced report runs");
    let text = std::fs::read_to_string(&path).unwrap();
    for name in ["numerics.png", "numerics.svg", "physics.png", "physics.svg"] {
        let p = dir.join(name);
        assert!(
            p.metadata().map(|m| m.len() > 1000).unwrap_or(false),
            "{name} missing or empty"
        );
    }
    // every table: a header, a separator and at least one row of numbers
    let lines: Vec<&str> = text.lines().collect();
    let mut tables = 0;
    for (k, l) in lines.iter().enumerate() {
        if l.starts_with("|---") || l.starts_with("| ---") {
            tables += 1;
            let row = lines.get(k + 1).copied().unwrap_or("");
            assert!(
                row.starts_with('|') && row.chars().any(|c| c.is_ascii_digit()),
                "empty table before line {k}: {row:?}"
            );
        }
    }
    assert!(tables >= 4, "{tables} tables");
    for title in ["Kernel numerics", "Physics", "Scene pruning"] {
        assert!(text.contains(title), "no section {title}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
