//! The order of a solve's substitutions ([`super::substitution`]), on one core or on two.
//!
//! On two cores ([`Split`]): a group's supernode writes rows of its own subtrees and rows of
//! the rest (the groups' ancestors), never the other group's. Forward, the two groups run at
//! the same time, the second on its own copy of the vector, each updating only its own rows;
//! the updates of the rest's rows are applied after both ([`Step::Rows`]), supernode by
//! supernode in ascending order, which is the order one core applies them in. The first group
//! applies its own in place when all its supernodes come before every other supernode (the
//! dissection order's two halves and separator): then they come first on one core too. Then
//! the rest, forward and backward, on one core (the middle), and the two groups backward at the
//! same time, each reading the rest's entries. Every entry receives the same operations in
//! the same order as on one core, so the solution is the same bit for bit. One `rayon::join`
//! covers the whole solve ([`Parallel::run`]).

use super::split::Split;
use super::substitution::{run, Factor, Step};
use super::Structure;
use std::ops::Range;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Mutex, PoisonError};

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
        match self.parallel.as_ref().filter(|_| two_cores) {
            Some(p) => p.run(factor, y, t, Mutex::new((copy, t2))),
            None => run(factor, &self.serial, y, t),
        }
    }
}

/// The stages of a run of the second group's steps in a two-core solve: ready to be claimed,
/// claimed by a thread, done.
struct Stages {
    ready: u8,
    claimed: u8,
    done: u8,
}

/// The second group's forward steps (ready at the start), then its backward steps (ready when
/// the middle is done).
const FORWARD: Stages = Stages {
    ready: 0,
    claimed: 1,
    done: 2,
};
const BACKWARD: Stages = Stages {
    ready: 3,
    claimed: 4,
    done: 5,
};
/// A thread panicked: no wait lasts (the join then raises the panic).
const ABANDONED: u8 = u8::MAX;

/// Sets the stage to [`ABANDONED`] if its thread unwinds, so that the other thread, which may
/// be waiting for a stage this one would have reached, does not wait for ever.
struct AbandonOnPanic<'a>(&'a AtomicU8);

impl Drop for AbandonOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.store(ABANDONED, Ordering::Release);
        }
    }
}

/// Moves `stage` from `from` to `to`; false if it was not at `from` (another thread claimed
/// the steps, or abandoned).
fn advance(stage: &AtomicU8, from: u8, to: u8) -> bool {
    stage
        .compare_exchange(from, to, Ordering::AcqRel, Ordering::Acquire)
        .is_ok()
}

/// Waits until `stage` reaches `at_least` (set by the other thread, which is running).
fn wait_for(stage: &AtomicU8, at_least: u8) {
    let mut spins = 0u32;
    while stage.load(Ordering::Acquire) < at_least {
        spins += 1;
        if spins.is_multiple_of(64) {
            std::thread::yield_now();
        } else {
            std::hint::spin_loop();
        }
    }
}

/// `to[r] = from[r]` for the ranges r of `runs`.
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

    /// The solve on two cores, in one `rayon::join`: the second thread is woken once, not once
    /// per phase, and waits for the middle spinning. The first closure does the first group's
    /// steps and the middle; the second group's forward and backward steps are claimed by
    /// whichever thread reaches them first (the first, if the second thread has not started
    /// by then: under load its start takes from 0.1 ms to several), so neither thread waits
    /// for steps no thread has started. `second`: the second group's vector and buffer.
    fn run(
        &self,
        factor: &Factor<'_>,
        y: &mut [f64],
        t: &mut Vec<f64>,
        second: Mutex<(&mut [f64], &mut Vec<f64>)>,
    ) {
        let stage = AtomicU8::new(FORWARD.ready);
        let (stage, second) = (&stage, &second);
        let lock = || second.lock().unwrap_or_else(PoisonError::into_inner);
        copy_dofs(y, lock().0, &self.second);
        // The second group's steps, by the thread that claims them.
        let claim = |stages: &Stages, steps: &[Step]| {
            if advance(stage, stages.ready, stages.claimed) {
                let mut guard = lock();
                let (copy, t2) = &mut *guard;
                run(factor, steps, copy, t2);
                drop(guard);
                advance(stage, stages.claimed, stages.done);
            }
        };
        rayon::join(
            || {
                let _abandon = AbandonOnPanic(stage);
                run(factor, &self.forward[0], y, t);
                claim(&FORWARD, &self.forward[1]);
                wait_for(stage, FORWARD.done);
                {
                    let mut guard = lock();
                    let (copy, _) = &mut *guard;
                    copy_dofs(copy, y, &self.second);
                    run(factor, &self.middle, y, t);
                    copy_dofs(y, copy, &self.rest);
                }
                advance(stage, FORWARD.done, BACKWARD.ready);
                run(factor, &self.backward[0], y, t);
                claim(&BACKWARD, &self.backward[1]);
                wait_for(stage, BACKWARD.done);
                copy_dofs(lock().0, y, &self.second);
            },
            || {
                let _abandon = AbandonOnPanic(stage);
                claim(&FORWARD, &self.forward[1]);
                wait_for(stage, BACKWARD.ready);
                claim(&BACKWARD, &self.backward[1]);
            },
        );
    }
}
