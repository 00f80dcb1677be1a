//! Nonlinear least squares: Levenberg-Marquardt on the normal equations, with Marquardt's
//! scaling (each parameter measured by its Jacobian column, so the formula's coefficients of
//! very different sizes are stepped alike) and Nielsen's damping update. The exact Jacobian
//! is used when given, else forward differences. A few dozen parameters against thousands of
//! rows: forming JᵀJ once per iteration (column dot products) costs a quarter of a QR of J,
//! and each damping trial is a Cholesky solve of the small system.

use std::cell::Cell;

use nalgebra::{Cholesky, DMatrix, DVector};

use crate::method::parallel::parallel_map;

/// Stop when an accepted step changes the sum of squares, or the scaled parameters, by less
/// than this relative amount: further digits change no test statistic.
const RELATIVE_TOLERANCE: f64 = 1e-6;

/// Stop when this many accepted steps have together lowered the sum of squares by less than
/// [`STALL_TOLERANCE`] of it: a crawl along a flat valley of the formula (e.g. combined-slip
/// shape and stiffness trading off), whose remaining gain changes no test statistic. A
/// looser rule leaves a fit short enough that a candidate tried after it is credited with
/// the rest.
const STALL_WINDOW: usize = 10;

/// See [`STALL_WINDOW`].
const STALL_TOLERANCE: f64 = 1e-5;

/// Damping at the start, relative to the scaled curvature (which is 1 on the diagonal).
const INITIAL_DAMPING: f64 = 1e-3;

/// A damping this large means no step along the gradient reduces the sum of squares.
const MAX_DAMPING: f64 = 1e16;

/// The outcome of one least-squares fit.
#[derive(Debug, Clone)]
pub struct Fit {
    pub params: Vec<f64>,
    /// Sum of squared residuals at `params`.
    pub sse: f64,
    /// Residual evaluations used (a Jacobian counted as one per parameter).
    pub evaluations: usize,
}

/// An exact Jacobian of the residuals at `x` into the (m x n) matrix; `false`: not available.
pub type Jacobian<'f> = &'f (dyn Fn(&[f64], &mut DMatrix<f64>) -> bool + 'f);

/// A step is halved at most this often to stay admissible (to 1/1024 of its length; the
/// probe of each parameter's own move at a bound is that long).
const MAX_STEP_HALVINGS: usize = 10;

/// Whether parameters lie in the admissible set (the fit never steps outside it).
pub type Feasible<'f> = &'f (dyn Fn(&[f64]) -> bool + 'f);

/// Evaluation budget of a fit, in multiples of (parameters + 1) residual evaluations. An
/// exact Jacobian does not count against it, so a fit with one may take about that many
/// iterations (with forward differences, each iteration spends parameters + 1).
pub const FULL_BUDGET: usize = 60;

/// Minimizes the sum of squares of `residuals(x, out)` (with `out.len() == m`) from `x0`,
/// spending at most `budget` times (parameters + 1) residual evaluations, with the exact
/// `jacobian` when given. With `feasible`, a step to parameters outside the admissible set is
/// halved until it stays inside; at a bound, the parameters whose own move leaves the set
/// are held and the step is solved for the others (else it is refused like one that does not
/// lower the sum of squares). A fit from an admissible `x0` stays admissible and goes on
/// along a bound. Returns `None`
/// if the residuals are not finite at `x0`.
pub fn least_squares(
    x0: &[f64],
    m: usize,
    budget: usize,
    residuals: &impl Fn(&[f64], &mut [f64]),
    jacobian: Option<Jacobian>,
    feasible: Option<Feasible>,
) -> Option<Fit> {
    let n = x0.len();
    let max_evaluations = budget * (n + 1);
    let evaluations = Cell::new(0);
    let mut eval = |x: &[f64], r: &mut DVector<f64>| {
        evaluations.set(evaluations.get() + 1);
        residuals(x, r.as_mut_slice());
        r.iter().all(|v| v.is_finite())
    };
    let mut s = Solver::start(x0, m, &mut eval)?;
    let exhausted = || evaluations.get() >= max_evaluations;
    let mut exact_jacobians = 0;
    // The sum of squares after each accepted step, for the stall rule.
    let mut history = vec![s.sse];
    while evaluations.get() < max_evaluations && s.sse > 0.0 && !stalled(&history) {
        let exact = jacobian.is_some_and(|exact| {
            s.jac.fill(0.0);
            exact(s.x.as_slice(), &mut s.jac)
        });
        if exact {
            exact_jacobians += 1;
        } else {
            forward_differences(&mut eval, s.x.as_slice(), &s.r, &mut s.jac);
        }
        let Some((curvature, gradient)) = s.normal_equations() else {
            break;
        };
        if !s.step(&mut eval, &curvature, &gradient, feasible, &exhausted) {
            break;
        }
        history.push(s.sse);
    }
    Some(Fit {
        params: s.x.as_slice().to_vec(),
        sse: s.sse,
        evaluations: evaluations.get() + exact_jacobians * n,
    })
}

/// Whether the last [`STALL_WINDOW`] accepted steps of a fit whose sums of squares are
/// `history` lowered it by less than [`STALL_TOLERANCE`] of it.
fn stalled(history: &[f64]) -> bool {
    let n = history.len();
    n > STALL_WINDOW
        && history[n - 1 - STALL_WINDOW] - history[n - 1] < STALL_TOLERANCE * history[n - 1]
}

/// The state of a fit: the iterate with its residuals, the Jacobian there, the trial
/// point, Marquardt's scale and the damping.
struct Solver {
    x: DVector<f64>,
    r: DVector<f64>,
    /// Sum of squared residuals at `x`.
    sse: f64,
    jac: DMatrix<f64>,
    trial_x: DVector<f64>,
    trial_r: DVector<f64>,
    scale: DVector<f64>,
    damping: f64,
    /// The factor the damping grows by at the next refused step.
    growth: f64,
}

impl Solver {
    /// The start at `x0` with `m` residuals; `None` if they are not finite there.
    fn start(
        x0: &[f64],
        m: usize,
        eval: &mut impl FnMut(&[f64], &mut DVector<f64>) -> bool,
    ) -> Option<Self> {
        let n = x0.len();
        let x = DVector::from_column_slice(x0);
        let mut r = DVector::zeros(m);
        if !eval(x.as_slice(), &mut r) {
            return None;
        }
        let sse = r.norm_squared();
        Some(Solver {
            x,
            r,
            sse,
            jac: DMatrix::zeros(m, n),
            trial_x: DVector::zeros(n),
            trial_r: DVector::zeros(m),
            scale: DVector::<f64>::zeros(n),
            damping: INITIAL_DAMPING,
            growth: 2.0,
        })
    }

    /// JᵀJ and Jᵀr from the Jacobian at the iterate, with Marquardt's scale updated;
    /// `None` when the Jacobian is not finite or every scale is zero.
    fn normal_equations(&mut self) -> Option<(DMatrix<f64>, DVector<f64>)> {
        let (curvature, gradient) = cross_products(&self.jac, &self.r);
        // A non-finite entry of the Jacobian makes its column's square non-finite.
        if (0..curvature.nrows()).any(|j| !curvature[(j, j)].is_finite())
            || gradient.iter().any(|g| !g.is_finite())
        {
            return None;
        }
        // Marquardt's scale only grows, as in MINPACK: a column that once mattered keeps its
        // measure when it flattens near the minimum.
        for j in 0..self.x.len() {
            self.scale[j] = self.scale[j].max(curvature[(j, j)].sqrt());
        }
        if self.scale.iter().all(|&s| s == 0.0) {
            return None;
        }
        Some((curvature, gradient))
    }

    /// Raises the damping after a refused step; whether it has passed [`MAX_DAMPING`].
    fn damp_more(&mut self) -> bool {
        self.damping *= self.growth;
        self.growth *= 2.0;
        self.damping > MAX_DAMPING
    }

    /// Steps from the current linearization, raising the damping until a trial is
    /// accepted. `false`: the fit stops (converged, damping too large, budget spent).
    fn step(
        &mut self,
        eval: &mut impl FnMut(&[f64], &mut DVector<f64>) -> bool,
        curvature: &DMatrix<f64>,
        gradient: &DVector<f64>,
        feasible: Option<Feasible>,
        exhausted: &dyn Fn() -> bool,
    ) -> bool {
        // Parameters held this iteration: each one whose move alone would leave the
        // admissible set.
        let mut held = vec![false; self.x.len()];
        loop {
            let (system, rhs) =
                damped_system(curvature, gradient, &self.scale, self.damping, &held);
            let Some(factor) = Cholesky::new(system) else {
                if self.damp_more() {
                    return false;
                }
                continue;
            };
            let mut step = factor.solve(&rhs);
            self.trial_x.copy_from(&self.x);
            self.trial_x += &step;
            let admissible = match feasible {
                Some(f) if !f(self.trial_x.as_slice()) => {
                    match bounded_step(f, &self.x, &mut step, &mut self.trial_x, &mut held) {
                        Bounded::Inside => true,
                        Bounded::Refused => false,
                        Bounded::Held => continue,
                    }
                }
                _ => true,
            };
            let predicted = -(2.0 * gradient.dot(&step) + step.dot(&(curvature * &step)));
            if admissible
                && eval(self.trial_x.as_slice(), &mut self.trial_r)
                && let Some(converged) = self.accept(predicted, &step)
            {
                return !converged;
            }
            if self.damp_more() || exhausted() {
                return false;
            }
        }
    }

    /// Judges a trial with finite residuals by the actual against the `predicted`
    /// reduction of the sum of squares: when both are positive the iterate moves to the
    /// trial and the damping is updated (Nielsen). `Some(converged)` when accepted.
    fn accept(&mut self, predicted: f64, step: &DVector<f64>) -> Option<bool> {
        let trial_sse = self.trial_r.norm_squared();
        let actual = self.sse - trial_sse;
        if actual > 0.0 && predicted > 0.0 {
            let rho = actual / predicted;
            self.damping *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
            self.growth = 2.0;
            let step_size = step.component_mul(&self.scale).norm();
            let size = self.x.component_mul(&self.scale).norm();
            let converged = (actual <= RELATIVE_TOLERANCE * self.sse
                && predicted <= RELATIVE_TOLERANCE * self.sse)
                || step_size <= RELATIVE_TOLERANCE * size;
            std::mem::swap(&mut self.x, &mut self.trial_x);
            std::mem::swap(&mut self.r, &mut self.trial_r);
            self.sse = trial_sse;
            Some(converged)
        } else {
            None
        }
    }
}

/// Rows of the Jacobian taken together by [`cross_products`]: their columns stay in cache
/// while every pair of them is multiplied.
const CROSS_BLOCK: usize = 256;

/// JᵀJ and Jᵀr, in one pass over the rows of `jac` (column-major) in blocks of
/// [`CROSS_BLOCK`]: each block's columns are read from memory once, not once per pair.
fn cross_products(jac: &DMatrix<f64>, r: &DVector<f64>) -> (DMatrix<f64>, DVector<f64>) {
    let (m, n) = jac.shape();
    let data = jac.as_slice();
    let r = r.as_slice();
    let column =
        |j: usize, rows: std::ops::Range<usize>| &data[j * m + rows.start..j * m + rows.end];
    // Row i of the upper triangle, with the gradient's entry i first, each entry summed over
    // the blocks in order: the same sums however the rows are spread over the cores. The
    // rows in groups of about equal work, each group over the blocks.
    let upper = parallel_map(&triangle_groups(n, CROSS_GROUPS), |group| {
        let mut rows: Vec<Vec<f64>> = group.clone().map(|i| vec![0.0; 1 + n - i]).collect();
        for start in (0..m).step_by(CROSS_BLOCK) {
            let block = start..(start + CROSS_BLOCK).min(m);
            for (i, row) in group.clone().zip(rows.iter_mut()) {
                let ci = column(i, block.clone());
                row[0] += dot(ci, &r[block.clone()]);
                for j in i..n {
                    row[1 + j - i] += dot(ci, column(j, block.clone()));
                }
            }
        }
        rows
    });
    let mut curvature = DMatrix::zeros(n, n);
    let mut gradient = DVector::zeros(n);
    for (i, row) in upper.iter().flatten().enumerate() {
        gradient[i] = row[0];
        for j in i..n {
            curvature[(i, j)] = row[1 + j - i];
            curvature[(j, i)] = row[1 + j - i];
        }
    }
    (curvature, gradient)
}

/// Groups of the rows of an upper triangle of `n` rows taken side by side by
/// [`cross_products`].
const CROSS_GROUPS: usize = 4;

/// The rows `0..n` of an upper triangle with a column before it (row i has `1 + n - i`
/// entries) as at most `groups` consecutive ranges of about equal entries.
fn triangle_groups(n: usize, groups: usize) -> Vec<std::ops::Range<usize>> {
    let total = n * (n + 3) / 2;
    let mut out = Vec::with_capacity(groups);
    let (mut start, mut done) = (0, 0);
    for i in 0..n {
        done += 1 + n - i;
        if done * groups >= total * (out.len() + 1) || i + 1 == n {
            out.push(start..i + 1);
            start = i + 1;
        }
    }
    out
}

/// The dot product of two equally long slices, over four running sums (which the compiler
/// keeps in vector registers).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (a4, a_rest) = a.as_chunks::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    let mut sums = [0.0; 4];
    for (x, y) in a4.iter().zip(b4) {
        for k in 0..4 {
            sums[k] += x[k] * y[k];
        }
    }
    let tail: f64 = a_rest.iter().zip(b_rest).map(|(x, y)| x * y).sum();
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

/// The damped normal equations `(JᵀJ + damping D²) step = -Jᵀr`, with each held
/// parameter's row and column replaced by the identity's (its step is zero).
fn damped_system(
    curvature: &DMatrix<f64>,
    gradient: &DVector<f64>,
    scale: &DVector<f64>,
    damping: f64,
    held: &[bool],
) -> (DMatrix<f64>, DVector<f64>) {
    let unit = |s: f64| if s > 0.0 { s } else { 1.0 };
    let mut system = curvature.clone();
    let mut rhs = -gradient;
    for j in 0..held.len() {
        system[(j, j)] += damping * unit(scale[j]).powi(2);
    }
    for j in (0..held.len()).filter(|&j| held[j]) {
        system.row_mut(j).fill(0.0);
        system.column_mut(j).fill(0.0);
        system[(j, j)] = 1.0;
        rhs[j] = 0.0;
    }
    (system, rhs)
}

/// What [`bounded_step`] made of a step leaving the admissible set.
enum Bounded {
    /// Halved until it stays inside.
    Inside,
    /// Parameters newly held: solve again for the others.
    Held,
    /// Neither: refused like a step that does not lower the sum of squares.
    Refused,
}

/// A step leaving the admissible set is halved until it stays inside, so the fit comes
/// up to a bound; where no halving stays inside (it is at the bound), the parameters whose
/// own move leaves the set are held and the step is solved again for the others, so the
/// fit goes on along the bound instead of stopping there.
fn bounded_step(
    f: Feasible,
    x: &DVector<f64>,
    step: &mut DVector<f64>,
    trial_x: &mut DVector<f64>,
    held: &mut [bool],
) -> Bounded {
    let full_step = step.clone();
    let mut halvings = 0;
    while !f(trial_x.as_slice()) {
        halvings += 1;
        if halvings > MAX_STEP_HALVINGS {
            return hold_at_bound(f, x, &full_step, held);
        }
        *step *= 0.5;
        trial_x.copy_from(x);
        *trial_x += &*step;
    }
    Bounded::Inside
}

/// At a bound, where no halving of `full_step` stays inside: the parameters whose own move
/// leaves the set are held, each probed at the smallest move that does (1/1024 of its step,
/// then twice that, up to the whole step), so a bound that only a joint move crosses (e.g. a
/// phase that is a product of two parameters) still holds the parameters that reach it first.
fn hold_at_bound(
    f: Feasible,
    x: &DVector<f64>,
    full_step: &DVector<f64>,
    held: &mut [bool],
) -> Bounded {
    let mut alone = x.clone();
    for halvings in (0..=MAX_STEP_HALVINGS).rev() {
        let share = 0.5f64.powi(halvings as i32);
        let mut newly_held = false;
        for j in 0..held.len() {
            if held[j] || full_step[j] == 0.0 {
                continue;
            }
            alone[j] = x[j] + full_step[j] * share;
            if !f(alone.as_slice()) {
                held[j] = true;
                newly_held = true;
            }
            alone[j] = x[j];
        }
        if newly_held {
            return Bounded::Held;
        }
    }
    Bounded::Refused
}

/// Forward differences of the residuals at `x` (whose residuals are `base`) into `jac`.
fn forward_differences(
    eval: &mut impl FnMut(&[f64], &mut DVector<f64>) -> bool,
    x: &[f64],
    base: &DVector<f64>,
    jac: &mut DMatrix<f64>,
) {
    let mut shifted_x = x.to_vec();
    let mut shifted = DVector::zeros(base.len());
    for j in 0..x.len() {
        let h = 1e-7 * x[j].abs().max(1e-4);
        shifted_x[j] = x[j] + h;
        eval(&shifted_x, &mut shifted);
        shifted_x[j] = x[j];
        jac.set_column(j, &((&shifted - base) / h));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_groups_cover_the_rows_in_about_equal_work() {
        for n in [0, 1, 2, 3, 5, 17, 32, 45] {
            let groups = triangle_groups(n, CROSS_GROUPS);
            assert!(groups.len() <= CROSS_GROUPS, "{n}: {groups:?}");
            let covered: Vec<usize> = groups.iter().flat_map(|g| g.clone()).collect();
            assert_eq!(covered, (0..n).collect::<Vec<_>>(), "{n}: {groups:?}");
            assert!(groups.iter().all(|g| !g.is_empty()));
            // No group holds more than its share by more than one row's entries.
            let work = |g: &std::ops::Range<usize>| g.clone().map(|i| 1 + n - i).sum::<usize>();
            let share = n * (n + 3) / 2 / CROSS_GROUPS;
            assert!(
                groups.iter().all(|g| work(g) <= share + n + 1),
                "{n}: {groups:?}"
            );
        }
        assert_eq!(triangle_groups(32, CROSS_GROUPS).len(), CROSS_GROUPS);
    }

    #[test]
    fn cross_products_are_those_of_the_transposed_jacobian() {
        // Rows not a multiple of the block nor of four; entries of mixed sign and scale.
        let (m, n) = (2 * CROSS_BLOCK + 7, 5);
        let jac = DMatrix::from_fn(m, n, |i, j| {
            ((i * 31 + j * 17) % 23) as f64 - 11.0 + 0.1 * j as f64
        });
        let r = DVector::from_fn(m, |i, _| ((i * 7) % 13) as f64 * 0.5 - 3.0);
        let (curvature, gradient) = cross_products(&jac, &r);
        let (jtj, jtr) = (jac.transpose() * &jac, jac.transpose() * &r);
        assert!((curvature - &jtj).abs().max() <= 1e-12 * jtj.abs().max());
        assert!((gradient - &jtr).abs().max() <= 1e-12 * jtr.abs().max());
    }

    #[test]
    fn recovers_the_parameters_of_a_nonlinear_curve() {
        // y = a exp(-b t) + c, sampled without noise.
        let (a, b, c) = (3.0, 0.7, -0.4);
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = t.iter().map(|t| a * (-b * t).exp() + c).collect();
        let residuals = |x: &[f64], out: &mut [f64]| {
            for i in 0..t.len() {
                out[i] = x[0] * (-x[1] * t[i]).exp() + x[2] - y[i];
            }
        };
        let fit = least_squares(
            &[1.0, 0.1, 0.0],
            t.len(),
            FULL_BUDGET,
            &residuals,
            None,
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
            &residuals,
            Some(&exact),
            None,
        )
        .unwrap();
        for (got, want) in with.params.iter().zip([a, b, c]) {
            assert!((got - want).abs() < 1e-6, "{:?}", with.params);
        }
    }

    #[test]
    fn recovers_a_badly_scaled_magic_formula_curve() {
        // y = D sin(C atan(B x)): parameters five orders of magnitude apart, as in the paper's
        // table; the scaling must step them alike.
        let (d, c, b) = (4000.0, 1.3, 0.12);
        let x: Vec<f64> = (0..200).map(|i| -15.0 + i as f64 * 0.15).collect();
        let curve = |p: &[f64], x: f64| p[0] * (p[1] * (p[2] * x).atan()).sin();
        let y: Vec<f64> = x.iter().map(|&x| curve(&[d, c, b], x)).collect();
        let residuals = |p: &[f64], out: &mut [f64]| {
            for i in 0..x.len() {
                out[i] = curve(p, x[i]) - y[i];
            }
        };
        let fit = least_squares(
            &[3000.0, 1.0, 0.05],
            x.len(),
            FULL_BUDGET,
            &residuals,
            None,
            None,
        )
        .unwrap();
        for (got, want) in fit.params.iter().zip([d, c, b]) {
            assert!((got / want - 1.0).abs() < 1e-6, "{:?}", fit.params);
        }
        // A budget of 2 x (parameters + 1) evaluations stops early, short of the minimum.
        let short =
            least_squares(&[3000.0, 1.0, 0.05], x.len(), 2, &residuals, None, None).unwrap();
        assert!(short.sse > fit.sse);
        let full_sse: f64 = (0..x.len())
            .map(|i| (curve(&[3000.0, 1.0, 0.05], x[i]) - y[i]).powi(2))
            .sum();
        assert!(
            short.sse < full_sse,
            "a step that is taken reduces the sum of squares"
        );
    }

    #[test]
    fn a_crawl_stops_and_progress_does_not() {
        // Ten steps each lowering the sum of squares by half a millionth of it: a crawl.
        let crawl: Vec<f64> = (0..=10).map(|k| 100.0 * (1.0 - 5e-7 * k as f64)).collect();
        assert!(stalled(&crawl));
        // Ten steps each lowering it by a thousandth: progress, and too few steps to judge.
        let progress: Vec<f64> = (0..=10).map(|k| 100.0 * 0.999f64.powi(k)).collect();
        assert!(!stalled(&progress));
        assert!(!stalled(&crawl[..10]));
    }

    #[test]
    fn non_finite_start_is_refused() {
        let fit = least_squares(
            &[0.0],
            1,
            FULL_BUDGET,
            &|x: &[f64], out: &mut [f64]| out[0] = 1.0 / x[0],
            None,
            None,
        );
        assert!(fit.is_none());
    }

    #[test]
    fn a_bound_only_a_joint_move_crosses_holds_the_parameters_that_reach_it() {
        // a + b <= 4 with 0.02 to spare: at 1/1024 of the step each of a and b alone stays
        // inside (0.0117 each) while together they leave (0.0234); at 2/1024 each alone
        // leaves. c does not enter the bound and is not held.
        let feasible = |p: &[f64]| p[0] + p[1] <= 4.0;
        let x = DVector::from_column_slice(&[1.99, 1.99, 0.0]);
        let mut step = DVector::from_column_slice(&[12.0, 12.0, 1.0]);
        let mut trial = &x + &step;
        let mut held = [false; 3];
        let outcome = bounded_step(&feasible, &x, &mut step, &mut trial, &mut held);
        assert!(matches!(outcome, Bounded::Held));
        assert_eq!(held, [true, true, false]);
        // With the only moving parameter already held, the step is refused.
        let nowhere = |p: &[f64]| p[2] <= 0.0 && p[0] + p[1] <= 4.0;
        let mut step = DVector::from_column_slice(&[0.0, 0.0, 1.0]);
        let mut trial = &x + &step;
        let mut held = [false, false, true];
        let outcome = bounded_step(&nowhere, &x, &mut step, &mut trial, &mut held);
        assert!(matches!(outcome, Bounded::Refused));
    }

    #[test]
    fn a_fit_from_an_admissible_start_stays_admissible() {
        // y = a x + b with the unconstrained optimum at a = 2; a <= 1.5 is admissible.
        let x: Vec<f64> = (0..40).map(|i| i as f64 * 0.25).collect();
        let y: Vec<f64> = x.iter().map(|x| 2.0 * x + 1.0).collect();
        let residuals = |p: &[f64], out: &mut [f64]| {
            for i in 0..x.len() {
                out[i] = p[0] * x[i] + p[1] - y[i];
            }
        };
        let free =
            least_squares(&[0.5, 0.0], x.len(), FULL_BUDGET, &residuals, None, None).unwrap();
        assert!((free.params[0] - 2.0).abs() < 1e-6, "{:?}", free.params);
        let bounded = |p: &[f64]| p[0] <= 1.5;
        let held = least_squares(
            &[0.5, 0.0],
            x.len(),
            FULL_BUDGET,
            &residuals,
            None,
            Some(&bounded),
        )
        .unwrap();
        assert!(held.params[0] <= 1.5, "{:?}", held.params);
        // It goes to the bound and fits the intercept there: at a = 1.5 the best b is
        // 1 + 0.5 mean(x).
        assert!(held.params[0] > 1.49, "{:?}", held.params);
        let mean_x = x.iter().sum::<f64>() / x.len() as f64;
        assert!(
            (held.params[1] - (1.0 + 0.5 * mean_x)).abs() < 0.05,
            "{:?}",
            held.params
        );
        let start_sse: f64 = (0..x.len()).map(|i| (0.5 * x[i] - y[i]).powi(2)).sum();
        assert!(
            held.sse < 0.1 * start_sse && held.sse > free.sse,
            "{} {} {} {:?}",
            held.sse,
            start_sse,
            free.sse,
            held.params
        );
    }
}
