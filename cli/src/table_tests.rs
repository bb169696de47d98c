//! The readers: every accepted spelling of a table gives the canonical CSV's numbers
//! bit for bit; every bad file a typed error naming what is wrong; arbitrary bytes never
//! a panic.

use super::*;
use npyz::WriterBuilder;
use proptest::prelude::*;

const PARTICLES: Columns = Columns {
    what: "particles",
    required: &["x", "y", "z", "radius"],
    refused: &[],
    refused_why: "",
    hint: "",
};
const FORCES_F: Columns = Columns {
    what: "forces",
    required: &["fx", "fy", "fz"],
    refused: &["tx", "ty", "tz"],
    refused_why: "need --moments FT",
    hint: "",
};

const CANONICAL: &str = "x,y,z,radius\n0,0,1.5,1\n2.5,0.5,1.75,1\n-0.5,2.75,2.5,1.2\n";

fn csv(text: &[u8], columns: &Columns) -> Result<(Table, Vec<String>), CliError> {
    read_csv("p.csv".to_string(), text, columns)
}

fn bits(t: &Table) -> Vec<Vec<u64>> {
    t.rows
        .iter()
        .map(|r| r.iter().map(|v| v.to_bits()).collect())
        .collect()
}

fn message(r: Result<impl std::fmt::Debug, CliError>) -> String {
    r.expect_err("must be refused").to_string()
}

#[test]
fn every_spelling_of_the_table_reads_as_the_canonical_csv() {
    let (want, ignored) = csv(CANONICAL.as_bytes(), &PARTICLES).unwrap();
    assert!(ignored.is_empty());
    assert_eq!(want.places, [2, 3, 4]);
    let spellings: [(&str, String); 7] = [
        (
            "reordered",
            "radius,z,x,y\n1,1.5,0,0\n1,1.75,2.5,0.5\n1.2,2.5,-0.5,2.75\n".to_string(),
        ),
        (
            "extra columns",
            "id,x,y,z,radius,type\n7,0,0,1.5,1,a\n8,2.5,0.5,1.75,1,b\n9,-0.5,2.75,2.5,1.2,c\n"
                .to_string(),
        ),
        ("crlf", CANONICAL.replace('\n', "\r\n")),
        ("bom", format!("\u{feff}{CANONICAL}")),
        (
            "quoted",
            "\"x\",\"y\",\"z\",\"radius\"\n\"0\",\"0\",\"1.5\",\"1\"\n\"2.5\",\"0.5\",\"1.75\",\"1\"\n\"-0.5\",\"2.75\",\"2.5\",\"1.2\"\n"
                .to_string(),
        ),
        (
            "spaces and case",
            " X , Y ,Z, Radius \n 0 , 0 , 1.5 , 1 \n2.5,  0.5,1.75,1\n-0.5,2.75 ,2.5,1.2\n"
                .to_string(),
        ),
        (
            "comments and blank lines",
            "# spheres\n\nx,y,z,radius\n0,0,1.5,1\n   \n# more\n2.5,0.5,1.75,1\n-0.5,2.75,2.5,1.2\n"
                .to_string(),
        ),
    ];
    for (what, text) in spellings {
        let (got, ignored) =
            csv(text.as_bytes(), &PARTICLES).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(bits(&got), bits(&want), "{what}");
        if what == "extra columns" {
            assert_eq!(ignored, ["id", "type"]);
        } else {
            assert!(ignored.is_empty(), "{what}: {ignored:?}");
        }
    }
    // lines count comments and blank lines
    let text = "# spheres\n\nx,y,z,radius\n0,0,1.5,1\n   \n# more\n2.5,0.5,1.75,1\n";
    assert_eq!(csv(text.as_bytes(), &PARTICLES).unwrap().0.places, [4, 7]);
    let text =
        "x,y,z,radius\r\n0,0,1.5,1\r\n# c\r\n2.5,0.5,1.75,1\r\n\"-0.5\",2.75,2.5,\"1.2\n\"\n";
    let (t, _) = csv(text.as_bytes(), &PARTICLES).unwrap();
    assert_eq!(t.places, [2, 4, 5]);
}

/// `values` as a `.npy` array of `shape` with the dtype `descr`, in `order`.
fn encode<T: npyz::Serialize>(
    descr: &str,
    shape: &[u64],
    order: Order,
    values: impl IntoIterator<Item = T>,
) -> Vec<u8> {
    let mut out = Vec::new();
    let mut w = npyz::WriteOptions::<T>::new()
        .dtype(npyz::DType::parse(&format!("'{descr}'")).unwrap())
        .shape(shape)
        .order(order)
        .writer(&mut out)
        .begin_nd()
        .unwrap();
    w.extend(values).unwrap();
    w.finish().unwrap();
    out
}

/// The canonical table as `.npy`: `dtype` ('<f8', '>f8', '<f4'), C or Fortran order.
fn npy(descr: &str, order: Order) -> Vec<u8> {
    let (table, _) = csv(CANONICAL.as_bytes(), &PARTICLES).unwrap();
    let (r, c) = (table.rows.len(), 4);
    let at = |k: usize| match order {
        Order::C => table.rows[k / c][k % c],
        Order::Fortran => table.rows[k % r][k / r],
    };
    let shape = [r as u64, c as u64];
    if descr.ends_with('4') {
        encode(descr, &shape, order, (0..r * c).map(|k| at(k) as f32))
    } else {
        encode(descr, &shape, order, (0..r * c).map(at))
    }
}

#[test]
fn npy_in_any_order_byte_order_and_precision_reads_as_the_csv() {
    let (want, _) = csv(CANONICAL.as_bytes(), &PARTICLES).unwrap();
    for descr in ["<f8", ">f8"] {
        for order in [Order::C, Order::Fortran] {
            let got = read_npy("p.npy".to_string(), &npy(descr, order), &PARTICLES).unwrap();
            assert_eq!(bits(&got), bits(&want), "{descr} {order:?}");
            assert_eq!(got.locus, Locus::Row);
            assert_eq!(got.place(2), "row 2");
        }
    }
    // float32: the same numbers rounded to single precision, widened exactly
    for order in [Order::C, Order::Fortran] {
        let got = read_npy("p.npy".to_string(), &npy("<f4", order), &PARTICLES).unwrap();
        let rounded: Vec<Vec<f64>> = want
            .rows
            .iter()
            .map(|r| r.iter().map(|&v| f64::from(v as f32)).collect())
            .collect();
        assert_eq!(got.rows, rounded);
    }
}

#[test]
fn bad_csv_files_name_what_is_wrong() {
    let m = message(csv(b"x,y,radius\n0,0,1\n", &PARTICLES));
    assert!(m.contains("p.csv line 1") && m.contains("missing z"), "{m}");
    let m = message(csv(b"0,0,1.5,1\n", &PARTICLES));
    assert!(m.contains("missing x, y, z, radius"), "{m}");
    let m = message(csv(b"x,y,z,radius,X\n", &PARTICLES));
    assert!(m.contains("the column x appears more than once"), "{m}");
    let m = message(csv(b"fx,fy,fz,ty\n", &FORCES_F));
    assert!(m.contains("column ty need --moments FT"), "{m}");
    let m = message(csv(b"x,y,z,radius,id\n0,0,2,1,a\n0,5,2\n", &PARTICLES));
    assert!(
        m.contains("p.csv line 3: expected 5 comma-separated fields (x,y,z,radius,id), found 3"),
        "{m}"
    );
    let m = message(csv(b"radius,x,y,z\n1,0,abc,2\n", &PARTICLES));
    assert!(
        m.contains("p.csv line 2: y = \"abc\" is not a number"),
        "{m}"
    );
    let m = message(csv(b"# only a comment\n", &PARTICLES));
    assert!(m.contains("the file is empty"), "{m}");
    // a field that is not UTF-8 is not a number, and the rest of the line is read
    let m = message(csv(b"x,y,z,radius\n0,\xff,2,1\n", &PARTICLES));
    assert!(
        m.contains("line 2: y = \"\u{fffd}\" is not a number"),
        "{m}"
    );
}

/// An NPY v1.0 file with this header dictionary and data.
fn npy_raw(dict: &str, data: &[u8]) -> Vec<u8> {
    let mut header = dict.to_string();
    // magic, version, length, text and newline: a multiple of 64 bytes
    let pad = (64 - (10 + header.len() + 1) % 64) % 64;
    header.push_str(&" ".repeat(pad));
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend((header.len() as u16).to_le_bytes());
    out.extend(header.as_bytes());
    out.extend(data);
    out
}

#[test]
fn bad_npy_files_name_what_is_wrong() {
    let read = |bytes: &[u8]| message(read_npy("p.npy".to_string(), bytes, &PARTICLES));
    let m = read(b"x,y,z,radius\n");
    assert!(
        m.starts_with("p.npy: not a readable NumPy .npy file"),
        "{m}"
    );
    let cases = [
        (
            "'<i8'",
            "(1, 4)",
            32,
            "dtype '<i8': expected a 2-D float64 or float32 array",
        ),
        (
            "'<f8'",
            "(2, 3)",
            48,
            "shape (2, 3): expected a 2-D float64 or float32 array of shape (N, 4)",
        ),
        ("'<f8'", "(8,)", 64, "shape (8): expected"),
        ("'<f8'", "(2, 4)", 40, "truncated"),
        // a header promising 2^62 x 4 values (the product overflows u64) allocates nothing
        ("'<f8'", "(4611686018427387904, 4)", 32, "truncated"),
        (
            "[('x', '<f8')]",
            "(1, 4)",
            32,
            "dtype [('x', '<f8'), ]: expected",
        ),
    ];
    for (descr, shape, bytes, needle) in cases {
        let dict = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': {shape}, }}");
        let m = read(&npy_raw(&dict, &vec![0; bytes]));
        assert!(m.contains(needle), "{m}");
    }
    // a forces file of the wrong width names the columns that do not apply
    let wide = npy_raw(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 6), }",
        &[0; 48],
    );
    let m = message(read_npy("f.npy".to_string(), &wide, &FORCES_F));
    assert!(
        m.contains("shape (1, 6)") && m.contains("tx, ty, tz need --moments FT"),
        "{m}"
    );
}

/// Byte strings that look like the start of a table in either format, then anything.
fn nasty_bytes() -> impl Strategy<Value = Vec<u8>> {
    let prefix = prop_oneof![
        Just(Vec::new()),
        Just(b"x,y,z,radius\n".to_vec()),
        Just(b"\xef\xbb\xbfradius,x,\"y\",z\r\n".to_vec()),
        Just(npy_raw(
            "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 4), }",
            &[]
        )),
        Just(b"\x93NUMPY\x02\x00".to_vec()),
    ];
    let tail = prop_oneof![
        proptest::collection::vec(any::<u8>(), 0..200),
        proptest::collection::vec(
            prop_oneof![
                Just(b','),
                Just(b'\n'),
                Just(b'\r'),
                Just(b'"'),
                Just(b'#'),
                Just(b' '),
                Just(b'1'),
                Just(b'e'),
                Just(b'-'),
                Just(b'.')
            ],
            0..200
        ),
    ];
    (prefix, tail).prop_map(|(mut p, t)| {
        p.extend(t);
        p
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2048, ..ProptestConfig::default() })]

    /// Any bytes: a table or a typed error, never a panic, and every row has the
    /// columns asked for.
    #[test]
    fn arbitrary_bytes_never_panic(bytes in nasty_bytes()) {
        for result in [
            csv(&bytes, &PARTICLES).map(|(t, _)| t),
            read_npy("p.npy".to_string(), &bytes, &PARTICLES),
        ] {
            match result {
                Ok(t) => {
                    prop_assert!(t.rows.iter().all(|r| r.len() == 4));
                    prop_assert_eq!(t.rows.len(), t.places.len());
                }
                Err(e) => prop_assert!(!e.to_string().is_empty()),
            }
        }
    }

    /// Any f64 written in shortest round-trip form (NaN, infinities, subnormals
    /// included) reads back bit for bit (NaN as NaN).
    #[test]
    fn any_number_round_trips(values in proptest::collection::vec(any::<f64>(), 4..40)) {
        let rows: Vec<&[f64]> = values.chunks_exact(4).collect();
        let mut text = String::from("x,y,z,radius\n");
        for r in &rows {
            text.push_str(&format!("{:?},{:?},{:?},{:?}\n", r[0], r[1], r[2], r[3]));
        }
        let (t, _) = csv(text.as_bytes(), &PARTICLES).unwrap();
        for (got, want) in t.rows.iter().zip(&rows) {
            for (g, w) in got.iter().zip(want.iter()) {
                prop_assert!(g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan()));
            }
        }
    }
}
