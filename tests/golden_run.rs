//! The default run (the embedded paper scene) writes the same numbers as commit f321b82 did
//! (`fits.csv`: as the merge of the Levenberg–Marquardt fits did), to the last printed digit:
//! `curves.csv`, `fits.csv` and `stability.csv` against the files in
//! `tests/golden/` (provenance in `tests/golden/README.md`). Columns are compared by name.

use std::collections::HashMap;
use std::path::Path;

mod binary;

/// Columns the current outputs have and the golden files do not (issue 11 adds `study` to
/// curves.csv).
const NEW_COLUMNS: &[(&str, &[&str])] = &[("curves.csv", &["study"])];

/// A CSV file as its header and rows of text cells.
fn read(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = r
        .headers()
        .expect("header")
        .iter()
        .map(String::from)
        .collect();
    let rows = r
        .records()
        .map(|rec| rec.expect("record").iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// Every golden column is present and equal cell by cell; the only other columns are the
/// listed new ones.
fn same(file: &str, out: &Path) {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(file);
    let (g_head, g_rows) = read(&golden);
    let (n_head, n_rows) = read(&out.join(file));
    let new: &[&str] = NEW_COLUMNS
        .iter()
        .find(|(f, _)| *f == file)
        .map_or(&[], |(_, c)| c);
    for c in &n_head {
        assert!(
            g_head.contains(c) || new.contains(&c.as_str()),
            "{file}: column {c} is neither in the golden file nor listed as new"
        );
    }
    let at: HashMap<&str, usize> = n_head
        .iter()
        .enumerate()
        .map(|(i, c)| (c.as_str(), i))
        .collect();
    assert_eq!(g_rows.len(), n_rows.len(), "{file}: number of rows");
    for (column, name) in g_head.iter().enumerate() {
        let &j = at
            .get(name.as_str())
            .unwrap_or_else(|| panic!("{file}: column {name} missing"));
        for (i, (g, n)) in g_rows.iter().zip(&n_rows).enumerate() {
            assert_eq!(
                g[column], n[j],
                "{file}: row {} column {name}: golden {:?}, now {:?}\n golden row {g:?}\n now    {n:?}",
                i + 2,
                g[column],
                n[j]
            );
        }
    }
}

#[test]
fn the_default_run_writes_the_golden_numbers() {
    let out = std::env::temp_dir().join(format!("activemuscle-golden-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    binary::run_quiet(None, &out);
    for file in ["curves.csv", "fits.csv", "stability.csv"] {
        same(file, &out);
    }
    let _ = std::fs::remove_dir_all(&out);
}
