//! The 22 scalar resistance functions of two spheres in Kim & Karrila's normalisation
//! (module docs of [`crate::two_sphere`]) and their names.

/// The ten force-torque resistance functions (Kim & Karrila normalisation, module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FtScalars {
    /// `X^A_11`, per `6 pi mu a1`.
    pub x11a: f64,
    /// `X^A_12`, per `6 pi mu a1`.
    pub x12a: f64,
    /// `Y^A_11`, per `6 pi mu a1`.
    pub y11a: f64,
    /// `Y^A_12`, per `6 pi mu a1`.
    pub y12a: f64,
    /// `Y^B_11`, per `4 pi mu a1^2`.
    pub y11b: f64,
    /// `Y^B_12`, per `4 pi mu a1^2`.
    pub y12b: f64,
    /// `X^C_11`, per `8 pi mu a1^3`.
    pub x11c: f64,
    /// `X^C_12`, per `8 pi mu a1^3`.
    pub x12c: f64,
    /// `Y^C_11`, per `8 pi mu a1^3`.
    pub y11c: f64,
    /// `Y^C_12`, per `8 pi mu a1^3`.
    pub y12c: f64,
}

/// All 22 resistance functions (Kim & Karrila normalisation, module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairScalars {
    /// `X^A_11`, per `6 pi mu a1`.
    pub x11a: f64,
    /// `X^A_12`, per `6 pi mu a1`.
    pub x12a: f64,
    /// `Y^A_11`, per `6 pi mu a1`.
    pub y11a: f64,
    /// `Y^A_12`, per `6 pi mu a1`.
    pub y12a: f64,
    /// `Y^B_11`, per `4 pi mu a1^2`.
    pub y11b: f64,
    /// `Y^B_12`, per `4 pi mu a1^2`.
    pub y12b: f64,
    /// `X^C_11`, per `8 pi mu a1^3`.
    pub x11c: f64,
    /// `X^C_12`, per `8 pi mu a1^3`.
    pub x12c: f64,
    /// `Y^C_11`, per `8 pi mu a1^3`.
    pub y11c: f64,
    /// `Y^C_12`, per `8 pi mu a1^3`.
    pub y12c: f64,
    /// `X^G_11`, per `4 pi mu a1^2`.
    pub x11g: f64,
    /// `X^G_12`, per `4 pi mu a1^2`.
    pub x12g: f64,
    /// `Y^G_11`, per `4 pi mu a1^2`.
    pub y11g: f64,
    /// `Y^G_12`, per `4 pi mu a1^2`.
    pub y12g: f64,
    /// `Y^H_11`, per `8 pi mu a1^3`.
    pub y11h: f64,
    /// `Y^H_12`, per `8 pi mu a1^3`.
    pub y12h: f64,
    /// `X^M_11`, per `(20/3) pi mu a1^3`.
    pub x11m: f64,
    /// `X^M_12`, per `(20/3) pi mu a1^3`.
    pub x12m: f64,
    /// `Y^M_11`, per `(20/3) pi mu a1^3`.
    pub y11m: f64,
    /// `Y^M_12`, per `(20/3) pi mu a1^3`.
    pub y12m: f64,
    /// `Z^M_11`, per `(20/3) pi mu a1^3`.
    pub z11m: f64,
    /// `Z^M_12`, per `(20/3) pi mu a1^3`.
    pub z12m: f64,
}

impl PairScalars {
    /// The 22 functions in the order of the struct (`x11a, x12a, y11a, ..., z12m`).
    pub fn to_array(&self) -> [f64; 22] {
        [
            self.x11a, self.x12a, self.y11a, self.y12a, self.y11b, self.y12b, self.x11c, self.x12c,
            self.y11c, self.y12c, self.x11g, self.x12g, self.y11g, self.y12g, self.y11h, self.y12h,
            self.x11m, self.x12m, self.y11m, self.y12m, self.z11m, self.z12m,
        ]
    }

    /// The force-torque part.
    pub fn ft(&self) -> FtScalars {
        FtScalars {
            x11a: self.x11a,
            x12a: self.x12a,
            y11a: self.y11a,
            y12a: self.y12a,
            y11b: self.y11b,
            y12b: self.y12b,
            x11c: self.x11c,
            x12c: self.x12c,
            y11c: self.y11c,
            y12c: self.y12c,
        }
    }

    /// The inverse of [`PairScalars::to_array`].
    pub fn from_array(v: [f64; 22]) -> Self {
        let [x11a, x12a, y11a, y12a, y11b, y12b, x11c, x12c, y11c, y12c, x11g, x12g, y11g, y12g, y11h, y12h, x11m, x12m, y11m, y12m, z11m, z12m] =
            v;
        PairScalars {
            x11a,
            x12a,
            y11a,
            y12a,
            y11b,
            y12b,
            x11c,
            x12c,
            y11c,
            y12c,
            x11g,
            x12g,
            y11g,
            y12g,
            y11h,
            y12h,
            x11m,
            x12m,
            y11m,
            y12m,
            z11m,
            z12m,
        }
    }
}

/// Names of the 22 functions in the order of [`PairScalars::to_array`].
pub const NAMES: [&str; 22] = [
    "X11A", "X12A", "Y11A", "Y12A", "Y11B", "Y12B", "X11C", "X12C", "Y11C", "Y12C", "X11G", "X12G",
    "Y11G", "Y12G", "Y11H", "Y12H", "X11M", "X12M", "Y11M", "Y12M", "Z11M", "Z12M",
];
