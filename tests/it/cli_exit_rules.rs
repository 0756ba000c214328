//! One exit rule for `run` and `tradeoff`, and failure lines that print numbers short.

use crate::binary::quietly;
use crate::scratch::scratch;

/// A trade-off of the frozen tangent alone, on a small mesh: its symmetric approximation does not
/// converge at every stretch (a measured result: its row says so).
const FROZEN: &str = "[[study]]\nkind = \"tradeoff\"\noptions = [\"frozen-tangent\"]\n\
                      stretch = [0.8, 1.3]\nnr = 2\nnz = 8\n";

#[test]
fn run_and_tradeoff_exit_alike_on_a_variant_that_does_not_converge() {
    let dir = scratch("exit-rule");
    let scene = dir.join("frozen.toml");
    std::fs::write(&scene, FROZEN).unwrap();
    let mut codes = Vec::new();
    for command in ["run", "tradeoff"] {
        let out = dir.join(command);
        let o = quietly(command, &scene, &out);
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        codes.push((o.status.code(), stdout));
    }
    // The variant that did not converge is a row of the table, not a failure of the study.
    let csv = std::fs::read_to_string(dir.join("tradeoff/tradeoff.csv")).unwrap();
    assert!(csv.contains("failed") || csv.contains("inf"), "{csv}");
    assert_eq!(
        codes[0].0, codes[1].0,
        "run: {}\ntradeoff: {}",
        codes[0].1, codes[1].1
    );
    assert_eq!(codes[0].0, Some(0), "{}", codes[0].1);
    assert!(!codes[0].1.contains("FAILED"), "{}", codes[0].1);
}

#[test]
fn failure_lines_write_an_extreme_stretch_short() {
    let dir = scratch("short-numbers");
    let scene = dir.join("big.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"uniaxial\"\nstretch = [1e308]\n\
         [[study]]\nkind = \"uniaxial\"\nname = \"across\"\ndirection = \"across\"\nstretch = [1e308]\n\
         [[study]]\nkind = \"stability\"\nstretch = [1e308]\n\
         [[study]]\nkind = \"biaxial\"\npairs = [[1e308, 1]]\n\
         [[study]]\nkind = \"shear\"\nshear = [1e308]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = quietly("run", &scene, &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(3), "{stdout}");
    let failed: Vec<&str> = stdout.lines().filter(|l| l.starts_with("FAILED")).collect();
    assert!(failed.len() >= 6, "{stdout}");
    for line in failed {
        let longest = line
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest <= 20, "a number of {longest} digits: {line}");
    }
    assert!(stdout.contains("lambda = 1e308"), "{stdout}");
}
