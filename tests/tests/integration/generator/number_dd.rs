use kernel_gen::number::dd::*;
use kernel_gen::number::scalar::Scalar;

fn rel(a: Dd, b: Dd) -> f64 {
    ((a - b).to_f64() / b.to_f64()).abs()
}

#[test]
fn third_times_three_is_one_beyond_f64() {
    let third = Dd::new(1.0) / Dd::new(3.0);
    let back = third * Dd::new(3.0);
    // Double-double carries ~106 bits: the residual is below 1e-31.
    assert!((back - Dd::new(1.0)).to_f64().abs() < 1e-31);
    // f64 alone would leave the low part: check it is really carried.
    assert!(third.lo != 0.0);
}

#[test]
fn sqrt_two_squared() {
    let s = Dd::new(2.0).sqrt();
    assert!(rel(s * s, Dd::new(2.0)) < 1e-31);
    // Known digits of sqrt(2): 1.41421356237309504880168872420969807856967
    let known = Dd::from_decimal("1.41421356237309504880168872420969807856967");
    assert!(rel(s, known) < 1e-31);
}

#[test]
fn pi_matches_decimal() {
    let known = Dd::from_decimal("3.14159265358979323846264338327950288419716939937510");
    assert!(rel(Dd::pi(), known) < 1e-31);
}

#[test]
fn powi_and_negative_powers() {
    let x = Dd::from_decimal("1.1");
    let p = x.powi(7);
    let known = Dd::from_decimal("1.9487171"); // 1.1^7 exactly
    assert!(rel(p, known) < 1e-31);
    assert!(rel(x.powi(-3) * x.powi(3), Dd::new(1.0)) < 1e-31);
}

/// `mantissa 10^exponent` from a decimal mantissa (powers of ten are exact in `Dd`
/// up to `10^22`).
fn sci(mantissa: &str, exponent: i32) -> Dd {
    let p = Dd::new(10.0).powi(exponent.abs());
    let m = Dd::from_decimal(mantissa);
    if exponent < 0 {
        m / p
    } else {
        m * p
    }
}

/// `exp` against 34-digit values of mpmath 1.4.1 (`mp.dps = 40`, `mp.exp`). The
/// tolerance 1e-30 is the reduction's six squarings (64 times `eps_dd`) with a
/// margin; a wrong term or constant is off by far more.
#[test]
fn exp_against_mpmath() {
    let cases = [
        ("-3.5", "0.03019738342231850073978629236361985", 0),
        ("-0.75", "0.4723665527410147071380465509432679", 0),
        ("0.001", "1.001000500166708341668055753993058", 0),
        ("1", "2.718281828459045235360287471352662", 0),
        ("2.5", "12.18249396070347343807017595116797", 0),
        ("30", "1.06864745815244621469904686507414", 13),
        ("-50", "1.928749847963917783017342816527013", -22),
    ];
    for (x, v, e) in cases {
        let got = Dd::from_decimal(x).exp();
        let want = sci(v, e);
        assert!(rel(got, want) < 1e-30, "exp({x}): {:e}", rel(got, want));
    }
    assert_eq!(Dd::new(0.0).exp(), Dd::new(1.0));
    assert_eq!(Dd::new(-800.0).exp(), Dd::new(0.0));
}

/// `erfc` and `erfcx` against 34-digit values of mpmath 1.4.1 (`mp.dps = 40`,
/// `mp.erfc`, `mp.exp(x**2) * mp.erfc(x)`), on both sides of the switch at 2 and for
/// a negative argument. The tolerance 1e-28: `1 - erf` just below 2 magnifies the
/// series' error `1e-30` by `erf/erfc = 213`.
#[test]
fn erfc_against_mpmath() {
    let cases = [
        ("-1.25", "1.922900128256458230136523481197281", 0),
        ("0.001", "0.9988716212090307636200515223430952", 0),
        ("0.3", "0.6713732405408725723610859521332434", 0),
        ("1.5", "0.03389485352468927293302373835405214", 0),
        ("1.999", "0.004698443348629489966328549906129597", 0),
        ("2", "0.004677734981047265837930743632747071", 0),
        ("2.75", "0.0001006219221196368369043919750869568", 0),
        ("5", "1.537459794428034850188343485383379", -12),
        ("7.5", "2.776649386030569100663966209322413", -26),
    ];
    for (x, v, e) in cases {
        let got = Dd::from_decimal(x).erfc();
        let want = sci(v, e);
        assert!(rel(got, want) < 1e-28, "erfc({x}): {:e}", rel(got, want));
    }
    for (x, v) in [
        ("0.5", "0.6156903441929258748707934226837419"),
        ("3", "0.179001151181389950419294815313621"),
    ] {
        let got = Dd::from_decimal(x).erfcx();
        let want = Dd::from_decimal(v);
        assert!(rel(got, want) < 1e-28, "erfcx({x}): {:e}", rel(got, want));
    }
    assert_eq!(Dd::new(0.0).erfc(), Dd::new(1.0));
}

#[test]
fn catastrophic_cancellation_is_resolved() {
    // (1 + 1e-20) - 1 is zero in f64 but exact here.
    let a = Dd::new(1.0) + Dd::new(1e-20);
    assert_eq!((a - Dd::new(1.0)).to_f64(), 1e-20);
}
