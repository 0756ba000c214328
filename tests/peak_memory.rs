//! Tests that read this process's own peak resident memory (VmHWM), so they run in a process of
//! their own: in the shared test binary (tests/it/) another test's allocations, running in parallel,
//! would count as theirs.

use activemuscle::fem::{FemError, Mesh};

const MIB: u64 = 1 << 20;

/// Peak resident memory of this process (VmHWM) in bytes, where /proc is available.
fn peak_resident() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[test]
fn a_mesh_beyond_the_memory_limit_is_refused_before_anything_is_allocated() {
    let before = peak_resident();
    // Its nodes alone would take 3.2 GB (the allocation that used to abort the process).
    let error = Mesh::structured(1.0, 4.0, 5000, 10_000, 1.0).unwrap_err();
    let message = error.to_string();
    println!("{message}");
    match &error {
        FemError::MemoryLimit {
            estimate, limit, ..
        } => assert!(*estimate > *limit as f64),
        other => panic!("expected a memory-limit error, got {other:?}"),
    }
    assert!(message.contains("5000 × 10000") && message.contains("GiB"));
    if let (Some(before), Some(after)) = (before, peak_resident()) {
        assert!(
            after - before < 100 * MIB,
            "the process grew by {} MiB",
            (after - before) / MIB
        );
    }
}
