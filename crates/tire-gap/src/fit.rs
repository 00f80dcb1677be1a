//! Nonlinear least squares: Levenberg-Marquardt (the `levenberg-marquardt` crate, a MINPACK
//! port) on a residual function, with an exact Jacobian when one is given, else forward
//! differences.

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Owned};

/// Stop when an iteration changes the sum of squares, or the parameters, by less than this
/// relative amount (the crate's default, 30 machine epsilons, spends most of its
/// evaluations on digits no test statistic can see).
const RELATIVE_TOLERANCE: f64 = 1e-8;

/// The outcome of one least-squares fit.
#[derive(Debug, Clone)]
pub struct Fit {
    pub params: Vec<f64>,
    /// Sum of squared residuals at `params`.
    pub sse: f64,
    /// Residual evaluations used (Jacobian columns included).
    pub evaluations: usize,
}

/// An exact Jacobian of the residuals at `x` into the (m x n) matrix; `false`: not available.
pub type Jacobian<'f> = &'f (dyn Fn(&[f64], &mut DMatrix<f64>) -> bool + 'f);

struct Problem<'f, F> {
    residuals: &'f F,
    jacobian: Option<Jacobian<'f>>,
    x: DVector<f64>,
    m: usize,
}

impl<F: Fn(&[f64], &mut [f64])> Problem<'_, F> {
    fn eval(&self, x: &[f64]) -> DVector<f64> {
        let mut r = DVector::zeros(self.m);
        (self.residuals)(x, r.as_mut_slice());
        r
    }
}

impl<F: Fn(&[f64], &mut [f64])> LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, F> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.eval(self.x.as_slice());
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let n = self.x.len();
        let mut jac = DMatrix::zeros(self.m, n);
        if let Some(exact) = self.jacobian
            && exact(self.x.as_slice(), &mut jac)
        {
            return jac.iter().all(|v| v.is_finite()).then_some(jac);
        }
        let base = self.eval(self.x.as_slice());
        let mut x = self.x.as_slice().to_vec();
        for j in 0..n {
            let h = 1e-7 * x[j].abs().max(1e-4);
            let keep = x[j];
            x[j] = keep + h;
            let shifted = self.eval(&x);
            x[j] = keep;
            let mut col = jac.column_mut(j);
            for i in 0..self.m {
                col[i] = (shifted[i] - base[i]) / h;
            }
        }
        jac.iter().all(|v| v.is_finite()).then_some(jac)
    }
}

/// Evaluation budget of a fit, in multiples of (parameters + 1) residual evaluations.
pub const FULL_BUDGET: usize = 60;

/// Minimizes the sum of squares of `residuals(x, out)` (with `out.len() == m`) from `x0`,
/// spending at most `budget` times (parameters + 1) residual evaluations, with the exact
/// `jacobian` when given. Returns `None` if the residuals are not finite at `x0`.
pub fn least_squares(
    x0: &[f64],
    m: usize,
    budget: usize,
    residuals: &impl Fn(&[f64], &mut [f64]),
    jacobian: Option<Jacobian>,
) -> Option<Fit> {
    let problem = Problem {
        residuals,
        jacobian,
        x: DVector::from_column_slice(x0),
        m,
    };
    problem.residuals()?;
    let (problem, report) = LevenbergMarquardt::new()
        .with_ftol(RELATIVE_TOLERANCE)
        .with_xtol(RELATIVE_TOLERANCE)
        .with_patience(budget)
        .minimize(problem);
    let r = problem.residuals()?;
    let evaluations = report.number_of_evaluations * (x0.len() + 1);
    Some(Fit {
        params: problem.x.as_slice().to_vec(),
        sse: r.norm_squared(),
        evaluations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_the_parameters_of_a_nonlinear_curve() {
        // y = a exp(-b t) + c, sampled without noise.
        let (a, b, c) = (3.0, 0.7, -0.4);
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = t.iter().map(|t| a * (-b * t).exp() + c).collect();
        let fit = least_squares(
            &[1.0, 0.1, 0.0],
            t.len(),
            FULL_BUDGET,
            &|x: &[f64], out: &mut [f64]| {
                for i in 0..t.len() {
                    out[i] = x[0] * (-x[1] * t[i]).exp() + x[2] - y[i];
                }
            },
            None,
        )
        .unwrap();
        for (got, want) in fit.params.iter().zip([a, b, c]) {
            assert!((got - want).abs() < 1e-6, "{:?}", fit.params);
        }
        assert!(fit.sse < 1e-12);
        // The same with the exact Jacobian: the same answer.
        let exact = |x: &[f64], jac: &mut DMatrix<f64>| {
            for (i, t) in t.iter().enumerate() {
                let e = (-x[1] * t).exp();
                jac[(i, 0)] = e;
                jac[(i, 1)] = -x[0] * t * e;
                jac[(i, 2)] = 1.0;
            }
            true
        };
        let with = least_squares(
            &[1.0, 0.1, 0.0],
            t.len(),
            FULL_BUDGET,
            &|x: &[f64], out: &mut [f64]| {
                for i in 0..t.len() {
                    out[i] = x[0] * (-x[1] * t[i]).exp() + x[2] - y[i];
                }
            },
            Some(&exact),
        )
        .unwrap();
        for (got, want) in with.params.iter().zip([a, b, c]) {
            assert!((got - want).abs() < 1e-6, "{:?}", with.params);
        }
    }

    #[test]
    fn non_finite_start_is_refused() {
        let fit = least_squares(
            &[0.0],
            1,
            FULL_BUDGET,
            &|x: &[f64], out: &mut [f64]| out[0] = 1.0 / x[0],
            None,
        );
        assert!(fit.is_none());
    }
}
