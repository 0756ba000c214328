//! The size of rayon's global thread pool, for the command line and the Python module alike:
//! `RAYON_NUM_THREADS` above [`THREADS_PER_CORE`] × the available cores is replaced by that
//! bound. Spawning a hundred thousand threads takes minutes, during which nothing else runs and
//! a SIGTERM waits.

/// The most threads the pool may have per available core.
pub const THREADS_PER_CORE: usize = 4;

/// The thread count to use instead of `asked` (the value of `RAYON_NUM_THREADS`) on `cores`
/// available cores: n_max = [`THREADS_PER_CORE`] × cores when `asked` reads as a count above
/// n_max; `None` otherwise (unset, unreadable or within the bound: rayon's own reading stands).
pub fn bound(asked: Option<&str>, cores: usize) -> Option<usize> {
    let most = THREADS_PER_CORE * cores.max(1);
    let asked = asked?.trim().parse::<usize>().ok()?;
    (asked > most).then_some(most)
}

/// Bounds rayon's global pool from the environment ([`bound`]); call it before the pool is
/// first used. Returns what to tell the user (a notice that the count was cut, or a warning
/// that the pool could not be bounded), `None` when there is nothing to say.
pub fn limit_global_pool() -> Option<String> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let asked = std::env::var("RAYON_NUM_THREADS").ok();
    let most = bound(asked.as_deref(), cores)?;
    let asked = format!(
        "RAYON_NUM_THREADS={} is more than {THREADS_PER_CORE} threads per available core \
         ({cores} cores)",
        asked.unwrap_or_default().trim()
    );
    Some(
        match rayon::ThreadPoolBuilder::new()
            .num_threads(most)
            .build_global()
        {
            Ok(()) => format!("notice: {asked}: using {most} threads"),
            Err(e) => format!("warning: {asked}, and the thread pool could not be bounded: {e}"),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::{bound, THREADS_PER_CORE};

    #[test]
    fn a_count_above_four_per_core_is_cut_to_four_per_core_and_nothing_else_is_touched() {
        // 2 cores: at most 8 threads.
        assert_eq!(THREADS_PER_CORE * 2, 8);
        assert_eq!(bound(Some("100000"), 2), Some(8));
        assert_eq!(bound(Some(" 9 "), 2), Some(8));
        for within in ["8", "1", "0"] {
            assert_eq!(bound(Some(within), 2), None, "{within}");
        }
        // Unset or unreadable: rayon decides (it ignores what it cannot read).
        for other in [None, Some(""), Some("many"), Some("-3"), Some("1e9")] {
            assert_eq!(bound(other, 2), None, "{other:?}");
        }
        // No core reported counts as one.
        assert_eq!(bound(Some("5"), 0), Some(4));
    }
}
