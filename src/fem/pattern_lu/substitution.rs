//! The substitutions of a solve, L y = P b then U z = y, one supernode at a time (a [`Step`]).
//!
//! Forward, supernode s (dofs b..e, off-diagonal rows R, all in its ancestors): its row swaps,
//! y₁ ← L₁₁⁻¹ y₁ column by column, and with each column k, y_R ← y_R − L₂₁[:, k] y_k. Backward,
//! in reverse: y₁ ← U₁₁⁻¹ (y₁ − U₁₂ y_R), reading the ancestors' entries only. The order of
//! the steps, on one core or two, is [`super::solve`]'s.

use super::Structure;

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

/// The factor a solve reads.
pub(super) struct Factor<'a> {
    pub st: &'a Structure,
    pub l: &'a [f64],
    pub u: &'a [f64],
    pub pivots: &'a [u32],
}

/// Runs `steps` on the permuted vector `y` (`t`: a buffer for the gathered rows), with AVX2
/// where the processor has it (checked at run time; the same operations in the same order).
pub(super) fn run(factor: &Factor<'_>, steps: &[Step], y: &mut [f64], t: &mut Vec<f64>) {
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
