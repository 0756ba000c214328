//! The substitutions of a solve, L y = P b then U z = y, supernode by supernode, on one core or
//! on two.
//!
//! Forward, supernode s (dofs b..e, off-diagonal rows R, all in its ancestors): its row swaps,
//! y₁ ← L₁₁⁻¹ y₁ column by column, and with each column k, y_R ← y_R − L₂₁[:, k] y_k. Backward,
//! in reverse: y₁ ← U₁₁⁻¹ (y₁ − U₁₂ y_R), reading the ancestors' entries only.
//!
//! On two cores ([`Split`]): a group's supernode writes rows of its own subtrees and rows of
//! the rest (the groups' ancestors), never the other group's. The two groups run at the same
//! time, the second on its own copy of the vector, each updating only its own rows; the
//! updates of the rest's rows are applied after the join ([`Step::Rows`]), supernode by
//! supernode in ascending order, which is the order one core applies them in. The first group
//! applies its own in place when all its supernodes come before every other supernode (the
//! dissection order's two halves and separator): then they come first on one core too. The
//! rest is then solved forward and backward on one core, and the two groups backward at the
//! same time, each reading the rest's entries. Every entry receives the same operations in
//! the same order as on one core, so the solution is the same bit for bit.

use super::split::Split;
use super::Structure;
use std::ops::Range;

/// One supernode's share of a solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Step {
    /// Row swaps and L₁₁ solve of supernode `s`, with the update of its off-diagonal rows
    /// before `until`.
    Forward { s: usize, until: usize },
    /// The update of supernode `s`'s off-diagonal rows from `from` on, by its solved block.
    Rows { s: usize, from: usize },
    /// U₁₁⁻¹ (y₁ − U₁₂ y_R) for supernode `s`.
    Backward { s: usize },
}

/// The steps of a solve on one core and, with a split, on two.
#[derive(Debug)]
pub(super) struct Schedule {
    /// Every supernode forward, then every supernode backward in reverse.
    serial: Vec<Step>,
    pub parallel: Option<Parallel>,
}

/// A solve on two cores: `forward` (the two groups at the same time; the second on its copy
/// of the vector, whose dofs `second` are copied to it before and back after), `middle` (one
/// core: the rest's rows updated by the groups, the rest forward and backward), `backward`
/// (the two groups at the same time; the rest's dofs `rest` copied to the second's vector
/// before, its own back after).
#[derive(Debug)]
pub(super) struct Parallel {
    forward: [Vec<Step>; 2],
    pub middle: Vec<Step>,
    backward: [Vec<Step>; 2],
    second: Vec<Range<usize>>,
    rest: Vec<Range<usize>>,
}

impl Schedule {
    pub fn new(st: &Structure, split: Option<&Split>) -> Self {
        let ns = st.begin.len();
        let forward = (0..ns).map(|s| Step::Forward {
            s,
            until: st.rows[s].len(),
        });
        let backward = (0..ns).rev().map(|s| Step::Backward { s });
        Self {
            serial: forward.chain(backward).collect(),
            parallel: split.map(|split| Parallel::new(st, split)),
        }
    }

    /// Runs the solve on the permuted vector `y`: on two cores if there is a split and
    /// `two_cores`, with `copy` the second core's vector; `gathered`, one buffer per core for
    /// the gathered rows.
    pub fn run(
        &self,
        factor: &Factor<'_>,
        y: &mut [f64],
        copy: &mut [f64],
        gathered: &mut [Vec<f64>; 2],
        two_cores: bool,
    ) {
        let [t, t2] = gathered;
        let Some(p) = self.parallel.as_ref().filter(|_| two_cores) else {
            return run(factor, &self.serial, y, t);
        };
        copy_dofs(y, copy, &p.second);
        rayon::join(
            || run(factor, &p.forward[0], y, t),
            || run(factor, &p.forward[1], copy, t2),
        );
        copy_dofs(copy, y, &p.second);
        run(factor, &p.middle, y, t);
        copy_dofs(y, copy, &p.rest);
        rayon::join(
            || run(factor, &p.backward[0], y, t),
            || run(factor, &p.backward[1], copy, t2),
        );
        copy_dofs(copy, y, &p.second);
    }
}

/// to[r] ← from[r] for the ranges r of `runs`.
fn copy_dofs(from: &[f64], to: &mut [f64], runs: &[Range<usize>]) {
    for run in runs {
        to[run.clone()].copy_from_slice(&from[run.clone()]);
    }
}

impl Parallel {
    fn new(st: &Structure, split: &Split) -> Self {
        let ns = st.begin.len();
        let mut in_rest = vec![false; ns];
        for &s in &split.rest {
            in_rest[s] = true;
        }
        // The group whose supernodes all come first, if one does, goes first (in place).
        let precedes = |g: usize| {
            let last = split.groups[g].last().copied().unwrap_or(0);
            let others = split.groups[1 - g].iter().chain(&split.rest);
            others.min().is_none_or(|&s| last < s)
        };
        let order = if !precedes(0) && precedes(1) {
            [1, 0]
        } else {
            [0, 1]
        };
        let first_in_place = precedes(order[0]);
        let [first, second] = order.map(|g| &split.groups[g]);
        // The rows of a group's supernode in the rest: the rows of its ancestors above the
        // group's subtrees, so the last rows of R.
        let rest_from = |s: usize| {
            let rows = &st.rows[s];
            rows.iter()
                .position(|&i| in_rest[st.supernode_of[i as usize] as usize])
                .unwrap_or(rows.len())
        };
        let mut middle: Vec<Step> = Vec::new();
        let mut forward = [Vec::new(), Vec::new()];
        for (g, group) in [first, second].into_iter().enumerate() {
            for &s in group {
                let (from, r) = (rest_from(s), st.rows[s].len());
                let in_place = g == 0 && first_in_place;
                let until = if in_place { r } else { from };
                forward[g].push(Step::Forward { s, until });
                if until < r {
                    middle.push(Step::Rows { s, from });
                }
            }
        }
        middle.extend(split.rest.iter().map(|&s| Step::Forward {
            s,
            until: st.rows[s].len(),
        }));
        middle.sort_by_key(|step| match *step {
            Step::Forward { s, .. } | Step::Rows { s, .. } | Step::Backward { s } => s,
        });
        middle.extend(split.rest.iter().rev().map(|&s| Step::Backward { s }));
        let backward = [first, second].map(|g| g.iter().rev().map(|&s| Step::Backward { s }));
        let dofs = |group: &[usize]| -> Vec<Range<usize>> {
            let mut runs: Vec<Range<usize>> = Vec::new();
            for &s in group {
                match runs.last_mut() {
                    Some(run) if run.end == st.begin[s] => run.end = st.end[s],
                    _ => runs.push(st.begin[s]..st.end[s]),
                }
            }
            runs
        };
        Self {
            forward,
            middle,
            backward: backward.map(Iterator::collect),
            second: dofs(second),
            rest: dofs(&split.rest),
        }
    }
}

/// The factor a solve reads.
pub(super) struct Factor<'a> {
    pub st: &'a Structure,
    pub l: &'a [f64],
    pub u: &'a [f64],
    pub pivots: &'a [u32],
}

/// Runs `steps` on the permuted vector `y` (`t`: a buffer for the gathered rows), with AVX2
/// where the processor has it (checked at run time; the same operations in the same order).
fn run(factor: &Factor<'_>, steps: &[Step], y: &mut [f64], t: &mut Vec<f64>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { run_avx2(factor, steps, y, t) };
    }
    run_plain(factor, steps, y, t)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2(factor: &Factor<'_>, steps: &[Step], y: &mut [f64], t: &mut Vec<f64>) {
    run_plain(factor, steps, y, t)
}

#[inline(always)]
fn run_plain(factor: &Factor<'_>, steps: &[Step], y: &mut [f64], t: &mut Vec<f64>) {
    for &step in steps {
        match step {
            Step::Forward { s, until } => factor.forward(s, until, y, t),
            Step::Rows { s, from } => factor.rows(s, from, y, t),
            Step::Backward { s } => factor.backward(s, y),
        }
    }
}

impl Factor<'_> {
    /// Supernode `s` forward, its off-diagonal rows before `until` updated. The rows R are
    /// gathered into `t`, updated as a dense vector (contiguous, so the loops vectorise) and
    /// scattered back.
    #[inline(always)]
    fn forward(&self, s: usize, until: usize, y: &mut [f64], t: &mut Vec<f64>) {
        let st = self.st;
        let (b, e) = (st.begin[s], st.end[s]);
        let rows = &st.rows[s][..until];
        let (w, ld) = (e - b, e - b + st.rows[s].len());
        for k in b..e {
            y.swap(k, self.pivots[k] as usize);
        }
        let l = &self.l[st.l_ptr[s]..st.l_ptr[s + 1]];
        t.clear();
        t.extend(rows.iter().map(|&i| y[i as usize]));
        let block = &mut y[b..e];
        for (k, column) in l.chunks_exact(ld).enumerate() {
            let yk = block[k];
            if yk == 0.0 {
                continue;
            }
            for (v, &lik) in block[k + 1..].iter_mut().zip(&column[k + 1..w]) {
                *v -= lik * yk;
            }
            for (v, &lik) in t.iter_mut().zip(&column[w..w + until]) {
                *v -= lik * yk;
            }
        }
        for (&i, &v) in rows.iter().zip(t.iter()) {
            y[i as usize] = v;
        }
    }

    /// The update of supernode `s`'s off-diagonal rows from `from` on by its solved block: the
    /// operations [`Self::forward`] leaves out of those rows, in the same order.
    #[inline(always)]
    fn rows(&self, s: usize, from: usize, y: &mut [f64], t: &mut Vec<f64>) {
        let st = self.st;
        let (b, e) = (st.begin[s], st.end[s]);
        let rows = &st.rows[s][from..];
        let (w, ld) = (e - b, e - b + st.rows[s].len());
        let l = &self.l[st.l_ptr[s]..st.l_ptr[s + 1]];
        t.clear();
        t.extend(rows.iter().map(|&i| y[i as usize]));
        for (&yk, column) in y[b..e].iter().zip(l.chunks_exact(ld)) {
            if yk == 0.0 {
                continue;
            }
            for (v, &lik) in t.iter_mut().zip(&column[w + from..]) {
                *v -= lik * yk;
            }
        }
        for (&i, &v) in rows.iter().zip(t.iter()) {
            y[i as usize] = v;
        }
    }

    /// Supernode `s` backward.
    #[inline(always)]
    fn backward(&self, s: usize, y: &mut [f64]) {
        let st = self.st;
        let (b, e) = (st.begin[s], st.end[s]);
        let rows = &st.rows[s];
        let (w, ld) = (e - b, e - b + rows.len());
        let l = &self.l[st.l_ptr[s]..st.l_ptr[s + 1]];
        let u = &self.u[st.u_ptr[s]..st.u_ptr[s + 1]];
        // The off-diagonal rows all come after the block: y[i] for i in R is in `later`.
        let (head, later) = y.split_at_mut(e);
        let block = &mut head[b..];
        for (column, &i) in u.chunks_exact(w).zip(rows) {
            let yi = later[i as usize - e];
            if yi != 0.0 {
                for (v, &uki) in block.iter_mut().zip(column) {
                    *v -= uki * yi;
                }
            }
        }
        for k in (0..w).rev() {
            let column = &l[k * ld..k * ld + k];
            let yk = block[k] / l[k + k * ld];
            block[k] = yk;
            for (v, &lik) in block[..k].iter_mut().zip(column) {
                *v -= lik * yk;
            }
        }
    }
}
