//! The Magic Formula 6.1 for Fx and Fy (Pacejka, *Tire and Vehicle Dynamics*, 3rd ed., 2012,
//! section 4.3.2; the MF-Tyre/MF-Swift 6.1 equation manual): pure slip with load, camber and
//! inflation-pressure terms, and combined slip with its weighting functions (Gxa, Gyk) and
//! the slip-ratio induced lateral force SVyk. Scaling factors (lambda) are 1, turn slip and
//! the low-speed corrections are left out: this is the steady-state model a reference fit
//! of rig data uses.
//!
//! Units: load N, slip angle and camber rad, slip ratio 1; the relative load
//! `dfz = (Fz - Fz0) / Fz0` and pressure `dpi = (p - p0) / p0` around the nominal values.
//! Axes are tire-gap's (the 1987 paper's): alpha > 0 gives Fy > 0, so the stiffness
//! pKy1 is positive where an ISO parameter file has it negative; the fit finds the signs.
//!
//! Each term says what must vary in the data for it to be identified ([`Needs`]); a reference
//! fit frees only those.

use mf87::Real;
use mf87::real::value;

/// What must vary in the data for a term to be identified.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Needs {
    pub load: bool,
    pub camber: bool,
    pub pressure: bool,
    pub combined: bool,
}

/// What the data varies (see [`Needs`]).
pub type Varies = Needs;

impl Needs {
    /// Whether data varying `what` identifies a term needing `self`.
    pub fn met_by(self, what: Varies) -> bool {
        (!self.load || what.load)
            && (!self.camber || what.camber)
            && (!self.pressure || what.pressure)
            && (!self.combined || what.combined)
    }
}

/// One coefficient: its name, what identifies it, its neutral or typical start.
#[derive(Debug, Clone, Copy)]
pub struct Term {
    pub name: &'static str,
    pub needs: Needs,
    /// The start of a fit (data-driven starts replace the peak and stiffness ones).
    pub start: f64,
}

const fn t(name: &'static str, needs: &str, start: f64) -> Term {
    let b = needs.as_bytes();
    let mut n = Needs {
        load: false,
        camber: false,
        pressure: false,
        combined: false,
    };
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'L' => n.load = true,
            b'G' => n.camber = true,
            b'P' => n.pressure = true,
            b'K' => n.combined = true,
            _ => {}
        }
        i += 1;
    }
    Term {
        name,
        needs: n,
        start,
    }
}

/// Fx's coefficients, in the order of the parameter vector (needs: L load, G camber,
/// P pressure, K combined slip).
pub const FX_TERMS: [Term; 26] = [
    t("pCx1", "", 1.6),
    t("pDx1", "", 1.5),
    t("pDx2", "L", -0.1),
    t("pDx3", "G", 0.0),
    t("pEx1", "", 0.0),
    t("pEx2", "L", 0.0),
    t("pEx3", "L", 0.0),
    t("pEx4", "", 0.0),
    t("pKx1", "", 25.0),
    t("pKx2", "L", 0.0),
    t("pKx3", "L", 0.0),
    t("pHx1", "", 0.0),
    t("pHx2", "L", 0.0),
    t("pVx1", "", 0.0),
    t("pVx2", "L", 0.0),
    t("ppx1", "P", 0.0),
    t("ppx2", "P", 0.0),
    t("ppx3", "P", 0.0),
    t("ppx4", "P", 0.0),
    t("rBx1", "K", 12.0),
    t("rBx2", "K", 8.0),
    t("rBx3", "KG", 0.0),
    t("rCx1", "K", 1.0),
    t("rEx1", "K", 0.0),
    t("rEx2", "KL", 0.0),
    t("rHx1", "K", 0.0),
];

const PCX1: usize = 0;
const PDX1: usize = 1;
const PDX2: usize = 2;
const PDX3: usize = 3;
const PEX1: usize = 4;
const PEX2: usize = 5;
const PEX3: usize = 6;
const PEX4: usize = 7;
const PKX1: usize = 8;
const PKX2: usize = 9;
const PKX3: usize = 10;
const PHX1: usize = 11;
const PHX2: usize = 12;
const PVX1: usize = 13;
const PVX2: usize = 14;
const PPX1: usize = 15;
const PPX2: usize = 16;
const PPX3: usize = 17;
const PPX4: usize = 18;
const RBX1: usize = 19;
const RBX2: usize = 20;
const RBX3: usize = 21;
const RCX1: usize = 22;
const REX1: usize = 23;
const REX2: usize = 24;
const RHX1: usize = 25;

/// Fy's coefficients, in the order of the parameter vector.
pub const FY_TERMS: [Term; 42] = [
    t("pCy1", "", 1.4),
    t("pDy1", "", 1.5),
    t("pDy2", "L", -0.1),
    t("pDy3", "G", 0.0),
    t("pEy1", "", 0.0),
    t("pEy2", "L", 0.0),
    t("pEy3", "", 0.0),
    t("pEy4", "G", 0.0),
    t("pEy5", "G", 0.0),
    t("pKy1", "", 30.0),
    t("pKy2", "L", 1.5),
    t("pKy3", "G", 0.0),
    t("pKy4", "L", 2.0),
    t("pKy5", "G", 0.0),
    t("pKy6", "G", 0.0),
    t("pKy7", "GL", 0.0),
    t("pHy1", "", 0.0),
    t("pHy2", "L", 0.0),
    t("pVy1", "", 0.0),
    t("pVy2", "L", 0.0),
    t("pVy3", "G", 0.0),
    t("pVy4", "GL", 0.0),
    t("ppy1", "P", 0.0),
    t("ppy2", "PL", 0.0),
    t("ppy3", "P", 0.0),
    t("ppy4", "P", 0.0),
    t("ppy5", "PG", 0.0),
    t("rBy1", "K", 8.0),
    t("rBy2", "K", 5.0),
    t("rBy3", "K", 0.0),
    t("rBy4", "KG", 0.0),
    t("rCy1", "K", 1.0),
    t("rEy1", "K", 0.0),
    t("rEy2", "KL", 0.0),
    t("rHy1", "K", 0.0),
    t("rHy2", "KL", 0.0),
    t("rVy1", "K", 0.0),
    t("rVy2", "KL", 0.0),
    t("rVy3", "KG", 0.0),
    t("rVy4", "K", 0.0),
    t("rVy5", "K", 1.0),
    t("rVy6", "K", 10.0),
];

const PCY1: usize = 0;
const PDY1: usize = 1;
const PDY2: usize = 2;
const PDY3: usize = 3;
const PEY1: usize = 4;
const PEY2: usize = 5;
const PEY3: usize = 6;
const PEY4: usize = 7;
const PEY5: usize = 8;
const PKY1: usize = 9;
const PKY2: usize = 10;
const PKY3: usize = 11;
const PKY4: usize = 12;
const PKY5: usize = 13;
const PKY6: usize = 14;
const PKY7: usize = 15;
const PHY1: usize = 16;
const PHY2: usize = 17;
const PVY1: usize = 18;
const PVY2: usize = 19;
const PVY3: usize = 20;
const PVY4: usize = 21;
const PPY1: usize = 22;
const PPY2: usize = 23;
const PPY3: usize = 24;
const PPY4: usize = 25;
const PPY5: usize = 26;
const RBY1: usize = 27;
const RBY2: usize = 28;
const RBY3: usize = 29;
const RBY4: usize = 30;
const RCY1: usize = 31;
const REY1: usize = 32;
const REY2: usize = 33;
const RHY1: usize = 34;
const RHY2: usize = 35;
const RVY1: usize = 36;
const RVY2: usize = 37;
const RVY3: usize = 38;
const RVY4: usize = 39;
const RVY5: usize = 40;
const RVY6: usize = 41;

/// The peak and stiffness coefficients that data-driven starts set: (peak, stiffness) of
/// Fx and of Fy.
pub const FX_PEAK_STIFFNESS: (usize, usize) = (PDX1, PKX1);
pub const FY_PEAK_STIFFNESS: (usize, usize) = (PDY1, PKY1);

/// The shape factors C of the pure-slip curves, which a feasible fit keeps in (0, 4).
pub const FX_SHAPE: usize = PCX1;
pub const FY_SHAPE: usize = PCY1;

/// Guards the divisions by C D and by the cornering stiffness, as the manual's epsilons.
const EPSILON: f64 = 1e-6;

/// One row: load \[N\], slip ratio, slip angle and camber \[rad\], and the relative pressure
/// `dpi` (0 without a pressure channel).
#[derive(Debug, Clone, Copy)]
pub struct Row {
    pub fz: f64,
    pub kappa: f64,
    pub alpha: f64,
    pub gamma: f64,
    pub dpi: f64,
}

/// The sign of a value as a constant (the curvature's asymmetry switches on it).
fn sign<T: Real>(x: T) -> f64 {
    if value(x) < 0.0 { -1.0 } else { 1.0 }
}

/// `x` capped at 1 from above (E <= 1 keeps the curve from folding back).
fn at_most_one<T: Real>(x: T) -> T {
    if value(x) > 1.0 { T::from(1.0) } else { x }
}

/// `D sin(C atan(B x - E (B x - atan(B x))))`.
fn magic<T: Real>(b: T, c: T, d: T, e: T, x: T) -> T {
    let bx = b * x;
    d * (c * (bx - e * (bx - bx.atan())).atan()).sin()
}

/// `cos(C atan(B x - E (B x - atan(B x))))`: a combined-slip weighting function's numerator.
fn weight<T: Real>(b: T, c: T, e: T, x: T) -> T {
    let bx = b * x;
    (c * (bx - e * (bx - bx.atan())).atan()).cos()
}

/// A divisor kept away from zero with its sign.
fn guarded<T: Real>(x: T) -> T {
    x + EPSILON * sign(x)
}

/// Fx at `row` with coefficients `p` ([`FX_TERMS`] order) around the nominal load `fz0` \[N\].
pub fn fx<T: Real>(p: &[T], fz0: f64, row: &Row) -> T {
    let fz = T::from(row.fz);
    let dfz = T::from((row.fz - fz0) / fz0);
    let dpi = T::from(row.dpi);
    let g2 = T::from(row.gamma.sin().powi(2));
    let shx = p[PHX1] + p[PHX2] * dfz;
    let kx = shx + row.kappa;
    let cx = p[PCX1];
    let mux = (p[PDX1] + p[PDX2] * dfz)
        * (p[PPX3] * dpi + p[PPX4] * dpi * dpi + 1.0)
        * (-(p[PDX3] * g2) + 1.0);
    let dx = mux * fz;
    let ex = at_most_one(
        (p[PEX1] + p[PEX2] * dfz + p[PEX3] * dfz * dfz) * (-(p[PEX4] * sign(kx)) + 1.0),
    );
    let kxk = fz
        * (p[PKX1] + p[PKX2] * dfz)
        * (p[PKX3] * dfz).exp()
        * (p[PPX1] * dpi + p[PPX2] * dpi * dpi + 1.0);
    let bx = kxk / guarded(cx * dx);
    let svx = fz * (p[PVX1] + p[PVX2] * dfz);
    let fx0 = magic(bx, cx, dx, ex, kx) + svx;
    // Combined slip: Gxa of the slip angle, narrowing as the slip ratio grows.
    let bxa = (p[RBX1] + p[RBX3] * g2) * (p[RBX2] * row.kappa).atan().cos();
    let (cxa, shxa) = (p[RCX1], p[RHX1]);
    let exa = at_most_one(p[REX1] + p[REX2] * dfz);
    let alpha_s = shxa + row.alpha.tan();
    let gxa = weight(bxa, cxa, exa, alpha_s) / weight(bxa, cxa, exa, shxa);
    gxa * fx0
}

/// Fy at `row` with coefficients `p` ([`FY_TERMS`] order) around the nominal load `fz0` \[N\].
pub fn fy<T: Real>(p: &[T], fz0: f64, row: &Row) -> T {
    let fz = T::from(row.fz);
    let dfz = T::from((row.fz - fz0) / fz0);
    let dpi = T::from(row.dpi);
    let g = row.gamma.sin();
    let (gt, g2) = (T::from(g), T::from(g * g));
    let tan_alpha = row.alpha.tan();
    let kya = p[PKY1]
        * fz0
        * (p[PPY1] * dpi + 1.0)
        * (-(p[PKY3] * g.abs()) + 1.0)
        * (p[PKY4]
            * (T::from(row.fz / fz0) / guarded((p[PKY2] + p[PKY5] * g2) * (p[PPY2] * dpi + 1.0)))
                .atan())
        .sin();
    let svyg = fz * (p[PVY3] + p[PVY4] * dfz) * gt;
    let kyg0 = fz * (p[PKY6] + p[PKY7] * dfz) * (p[PPY5] * dpi + 1.0);
    let shy = p[PHY1] + p[PHY2] * dfz + (kyg0 * gt - svyg) / guarded(kya);
    let ay = shy + tan_alpha;
    let cy = p[PCY1];
    let muy = (p[PDY1] + p[PDY2] * dfz)
        * (p[PPY3] * dpi + p[PPY4] * dpi * dpi + 1.0)
        * (-(p[PDY3] * g2) + 1.0);
    let dy = muy * fz;
    let ey = at_most_one(
        (p[PEY1] + p[PEY2] * dfz) * (p[PEY5] * g2 + 1.0 - (p[PEY3] + p[PEY4] * gt) * sign(ay)),
    );
    let by = kya / guarded(cy * dy);
    let svy = fz * (p[PVY1] + p[PVY2] * dfz) + svyg;
    let fy0 = magic(by, cy, dy, ey, ay) + svy;
    // Combined slip: Gyk of the slip ratio, narrowing as the slip angle grows, and the lateral
    // force the slip ratio induces (SVyk).
    let byk = (p[RBY1] + p[RBY4] * g2) * ((T::from(tan_alpha) - p[RBY3]) * p[RBY2]).atan().cos();
    let (cyk, shyk) = (p[RCY1], p[RHY1] + p[RHY2] * dfz);
    let eyk = at_most_one(p[REY1] + p[REY2] * dfz);
    let kappa_s = shyk + row.kappa;
    let gyk = weight(byk, cyk, eyk, kappa_s) / weight(byk, cyk, eyk, shyk);
    let dvyk =
        muy * fz * (p[RVY1] + p[RVY2] * dfz + p[RVY3] * gt) * (p[RVY4] * tan_alpha).atan().cos();
    let svyk = dvyk * (p[RVY5] * (p[RVY6] * row.kappa).atan()).sin();
    gyk * fy0 + svyk
}

/// The channel's formula: Fx or Fy.
pub type Formula<T> = fn(&[T], f64, &Row) -> T;

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    fn starts(terms: &[Term]) -> Vec<f64> {
        terms.iter().map(|t| t.start).collect()
    }

    fn row(fz: f64, kappa: f64, alpha_deg: f64, gamma_deg: f64) -> Row {
        Row {
            fz,
            kappa,
            alpha: alpha_deg.to_radians(),
            gamma: gamma_deg.to_radians(),
            dpi: 0.0,
        }
    }

    #[test]
    fn pure_slip_curves_by_hand() {
        // Fx at Fz0 with only C, D, K: D sin(C atan(B kappa)), B = K / (C D) per unit load.
        let mut p = vec![0.0; FX_TERMS.len()];
        (p[PCX1], p[PDX1], p[PKX1]) = (1.6, 1.5, 25.0);
        let fz0 = 1000.0;
        let k: f64 = 0.05;
        let b = 25.0 * fz0 / (1.6 * 1500.0);
        let want = 1500.0 * (1.6 * (b * k).atan()).sin();
        let got = fx(&p, fz0, &row(fz0, k, 0.0, 0.0));
        assert!((got - want).abs() < 1e-6 * want, "{got} vs {want}");
        // With the combined terms neutral (rBx1 = 0), the slip angle changes nothing.
        assert_eq!(fx(&p, fz0, &row(fz0, k, 6.0, 0.0)), got);
        // The slope at zero slip is the stiffness Kxk = pKx1 Fz at the nominal load.
        let h = 1e-7;
        let slope = (fx(&p, fz0, &row(fz0, h, 0.0, 0.0)) - fx(&p, fz0, &row(fz0, -h, 0.0, 0.0)))
            / (2.0 * h);
        assert!((slope / (25.0 * fz0) - 1.0).abs() < 1e-4, "{slope}");
        // Fy: the cornering stiffness at zero slip is pKy1 Fz0 sin(pKy4 atan(1 / pKy2)).
        let q = starts(&FY_TERMS);
        let mut q0 = q.clone();
        q0[RBY1] = 0.0;
        q0[RVY1] = 0.0;
        let slope = (fy(&q0, fz0, &row(fz0, 0.0, 1e-5, 0.0))
            - fy(&q0, fz0, &row(fz0, 0.0, -1e-5, 0.0)))
            / (2.0 * 1e-5_f64.to_radians());
        let kya = 30.0 * fz0 * (2.0 * (1.0f64 / 1.5).atan()).sin();
        assert!((slope / kya - 1.0).abs() < 1e-4, "{slope} vs {kya}");
    }

    #[test]
    fn combined_slip_narrows_each_force_by_the_other_slip() {
        let (fz0, p, q) = (1000.0, starts(&FX_TERMS), starts(&FY_TERMS));
        let pure_x = fx(&p, fz0, &row(fz0, 0.08, 0.0, 0.0));
        let comb_x = fx(&p, fz0, &row(fz0, 0.08, 6.0, 0.0));
        assert!(comb_x < pure_x && comb_x > 0.0, "{comb_x} {pure_x}");
        let pure_y = fy(&q, fz0, &row(fz0, 0.0, 6.0, 0.0));
        let comb_y = fy(&q, fz0, &row(fz0, 0.1, 6.0, 0.0));
        assert!(comb_y < pure_y && comb_y > 0.0, "{comb_y} {pure_y}");
        // The weights are 1 at zero other slip (no shifts).
        assert!((fx(&p, fz0, &row(fz0, 0.08, 0.0, 0.0)) - pure_x).abs() < 1e-9);
        // SVyk: the slip ratio induces a lateral force at zero slip angle.
        let mut v = q.clone();
        v[RVY1] = 0.05;
        assert!(fy(&v, fz0, &row(fz0, 0.1, 0.0, 0.0)).abs() > 10.0);
        assert!(fy(&v, fz0, &row(fz0, 0.0, 0.0, 0.0)).abs() < 1e-9);
    }

    #[test]
    fn dual_numbers_give_the_derivatives_of_every_coefficient() {
        let fz0 = 1100.0;
        let mut p = starts(&FY_TERMS);
        for (i, v) in p.iter_mut().enumerate() {
            *v += 0.01 * (i % 5) as f64;
        }
        let r = Row {
            fz: 1500.0,
            kappa: 0.04,
            alpha: 0.07,
            gamma: 0.03,
            dpi: 0.1,
        };
        for k in 0..p.len() {
            let d: Vec<Dual64> = p
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    let x = Dual64::from(v);
                    if i == k { x.derivative() } else { x }
                })
                .collect();
            let exact = fy(&d, fz0, &r).eps;
            let h = 1e-6 * p[k].abs().max(1.0);
            let at = |dv: f64| {
                let mut q = p.clone();
                q[k] += dv;
                fy(&q, fz0, &r)
            };
            let fd = (at(h) - at(-h)) / (2.0 * h);
            assert!(
                (exact - fd).abs() <= 1e-5 * fd.abs().max(1.0),
                "{}: {exact} vs {fd}",
                FY_TERMS[k].name
            );
        }
    }
}
