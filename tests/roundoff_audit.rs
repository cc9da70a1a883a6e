//! Issue 22: "the report, README and figures carry no digit that a 1e-13 perturbation changes".
//!
//! `massredist reproduce --roundoff-audit` starts every run (the base run of every case, not only
//! the report's own perturbed copies) from U⁰, V⁰ perturbed by ≤ 1e-13 with a pattern the report
//! does not use itself ([`massredist::problem::set_roundoff_audit`]). Its report.md and the text
//! of its figures must say what the plain run says: line for line the same words, and every
//! number the same or differing only by the rounding of its last printed digit (two printings of
//! values within half a unit of each other's last digit). Timings are the one exception.
//!
//! The test runs the reduced configuration (`--quick`) both ways. The full one is checked the
//! same way by pointing `MASSREDIST_AUDIT_DIRS=PLAIN:PERTURBED` at two finished `reproduce`
//! folders (the closing note of issue 22 says which run).

use std::path::{Path, PathBuf};
use std::process::Command;

/// A number as printed: its value and half a unit of its last printed digit; or a band `lo–hi`
/// of a round-off sensitive quantity (`value` = lo, `high` = hi).
#[derive(Debug, Clone, Copy)]
struct Printed {
    value: f64,
    half_unit: f64,
    /// An integer without decimals or exponent (a count): must be equal.
    exact: bool,
    /// The upper end of a band (None for a number).
    high: Option<(f64, f64)>,
    /// A verdict (bounded, grows, diverged) or a band of them: compared by rank, not widened.
    verdict: bool,
}

impl Printed {
    /// The values this printing stands for: its rounding interval, or the band's widened by the
    /// rounding of its ends.
    /// A band is widened by its own width on each side: it is the spread of a few samples of a
    /// round-off sensitive value, and the spread of another few samples (the audit perturbs every
    /// run, copies included) need not overlap it exactly; two sample ranges of five overlap
    /// after that widening unless the distributions differ.
    fn interval(&self) -> (f64, f64) {
        match self.high {
            None => (self.value - self.half_unit, self.value + self.half_unit),
            Some((hi, hu)) => {
                let w = if self.verdict || !hi.is_finite() { 0.0 } else { hi - self.value };
                (self.value - self.half_unit - w, hi + hu + w)
            }
        }
    }

    /// Two printings are compatible if they could describe the same value: equal counts; numbers
    /// within the rounding of their last digits; a band (the spread of a round-off sensitive
    /// quantity over the report's runs) overlapping the other band or containing the number.
    fn compatible(&self, other: &Printed) -> bool {
        if self.exact && other.exact && self.high.is_none() && other.high.is_none() {
            return self.value == other.value;
        }
        let ((a0, a1), (b0, b1)) = (self.interval(), other.interval());
        let slack = 1e-9 * (a0.abs() + a1.abs() + b0.abs() + b1.abs());
        a0 <= b1 + slack && b0 <= a1 + slack
    }
}

/// The verdicts of a run's energy, on their order (a range of them is a band: `bounded–grows`).
const VERDICTS: [&str; 3] = ["bounded", "grows", "diverged"];

/// Splits a line into its words (numbers replaced by `#`) and its numbers.
fn tokens(line: &str) -> (String, Vec<Printed>) {
    let chars: Vec<char> = line.chars().collect();
    let mut skeleton = String::new();
    let mut numbers = Vec::new();
    let mut i = 0;
    let word = |j: usize| chars[j].is_alphanumeric() || chars[j] == '_' || chars[j] == '.';
    while i < chars.len() {
        // "varies" (some runs have the value, others not) stands for any value; the verdict
        // words for their rank.
        let rest: String = chars[i..chars.len().min(i + 8)].iter().collect();
        let at_word_start = i == 0 || !chars[i - 1].is_alphanumeric();
        if at_word_start && rest.starts_with("varies") {
            let any = Printed { value: f64::NEG_INFINITY, half_unit: 0.0, exact: false, high: None, verdict: false };
            push(&mut skeleton, &mut numbers, Printed { high: Some((f64::INFINITY, 0.0)), ..any });
            i += "varies".len();
            continue;
        }
        if let Some(rank) = VERDICTS.iter().position(|w| at_word_start && rest.starts_with(w)) {
            let verdict = Printed { value: rank as f64, half_unit: 0.0, exact: false, high: None, verdict: true };
            push(&mut skeleton, &mut numbers, verdict);
            i += VERDICTS[rank].len();
            continue;
        }
        // Digits inside a word ("fig12", "T3", "x1e-3") are part of the word.
        let starts = chars[i].is_ascii_digit()
            && (i == 0 || !word(i - 1))
            && !(i >= 2 && matches!(chars[i - 1], '-' | '−') && word(i - 2));
        if !starts {
            skeleton.push(chars[i]);
            i += 1;
            continue;
        }
        // A sign directly before the digits ('+', ASCII '-' or the minus sign U+2212) belongs to it.
        let negative = skeleton.ends_with('-') || skeleton.ends_with('−');
        if negative || skeleton.ends_with('+') {
            skeleton.pop();
        }
        let (end, mut number) = number_at(&chars, i);
        if negative {
            number.value = -number.value;
        }
        push(&mut skeleton, &mut numbers, number);
        i = end;
    }
    (skeleton, numbers)
}

/// The unsigned number whose digits start at `chars[start]` (digits, decimals, an exponent
/// `e±k`) and where it ends.
fn number_at(chars: &[char], start: usize) -> (usize, Printed) {
    let digits = |mut i: usize| {
        while i < chars.len() && chars[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits(start);
    let mut decimals = 0i32;
    if i + 1 < chars.len() && chars[i] == '.' && chars[i + 1].is_ascii_digit() {
        let end = digits(i + 1);
        decimals = (end - i - 1) as i32;
        i = end;
    }
    let mantissa: f64 = chars[start..i].iter().collect::<String>().parse().unwrap_or(f64::NAN);
    let (mut exponent, mut has_exponent) = (0i32, false);
    if i + 1 < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
        let sign = usize::from(matches!(chars[i + 1], '-' | '+'));
        let end = digits(i + 1 + sign);
        if end > i + 1 + sign {
            exponent = chars[i + 1..end].iter().collect::<String>().parse().unwrap_or(0);
            has_exponent = true;
            i = end;
        }
    }
    let printed = Printed {
        value: mantissa * 10f64.powi(exponent),
        half_unit: 0.5 * 10f64.powi(exponent - decimals),
        exact: decimals == 0 && !has_exponent,
        high: None,
        verdict: false,
    };
    (i, printed)
}

/// Appends a printed value: as the upper end of a band if the skeleton ends with `#–` or
/// `# to ` (`lo–hi`, `lo to hi`), else as a new value `#`.
fn push(skeleton: &mut String, numbers: &mut Vec<Printed>, p: Printed) {
    let cut = if skeleton.ends_with("#–") {
        1
    } else if skeleton.ends_with("# to ") {
        4
    } else {
        numbers.push(p);
        skeleton.push('#');
        return;
    };
    for _ in 0..cut {
        skeleton.pop();
    }
    let last = numbers.last_mut().expect("a band's lower end");
    if p.value < last.value {
        // A band of signed values may be written high to low ("+0.01 to -0.23").
        (last.value, last.half_unit, last.high) = (p.value, p.half_unit, Some((last.value, last.half_unit)));
    } else {
        last.high = Some((p.value, p.half_unit));
    }
    last.exact &= p.exact;
}

/// Lines that report a time or a machine measurement (they differ from run to run by design).
fn is_timing(line: &str) -> bool {
    ["wall", "CPU", " ms", "seconds", "cpu_", " s)", " s,", " s;", " s.", "µs", "ns/", "per step"]
        .iter()
        .any(|w| line.contains(w))
}

/// The columns of a markdown table header that hold timings.
fn timing_columns(header: &str) -> Vec<usize> {
    let cells: Vec<&str> = header.split('|').collect();
    (0..cells.len())
        .filter(|&k| {
            ["CPU", "cpu", "wall", "time (s)", " s/", "(ms)", "(s)", "of which steps"]
                .iter()
                .any(|w| cells[k].contains(w))
        })
        .collect()
}

/// A table row without the cells of `skip`.
fn without(line: &str, skip: &[usize]) -> String {
    line.split('|').enumerate().filter(|(k, _)| !skip.contains(k)).map(|(_, c)| c).collect::<Vec<_>>().join("|")
}

/// The differences between two texts that are more than the rounding of a last printed digit
/// (timings left out: prose lines that state one, and the timing columns of tables).
fn incompatible(plain: &str, perturbed: &str) -> Vec<String> {
    let (a, b): (Vec<&str>, Vec<&str>) = (plain.lines().collect(), perturbed.lines().collect());
    if a.len() != b.len() {
        return vec![format!("{} lines against {}", a.len(), b.len())];
    }
    let mut out = Vec::new();
    let mut skip = Vec::new();
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        let table = x.starts_with('|');
        if table && a.get(k + 1).is_some_and(|n| n.starts_with("|---") || n.starts_with("|:-")) {
            skip = timing_columns(x);
        } else if !table {
            skip.clear();
        }
        let (x, y) = if table { (without(x, &skip), without(y, &skip)) } else { (x.to_string(), y.to_string()) };
        if x == y || (!table && is_timing(&x)) {
            continue;
        }
        let ((sx, nx), (sy, ny)) = (tokens(&x), tokens(&y));
        let same = sx == sy && nx.len() == ny.len() && nx.iter().zip(&ny).all(|(p, q)| p.compatible(q));
        if !same {
            out.push(format!("line {}:\n  plain:     {x}\n  perturbed: {y}", k + 1));
        }
    }
    out
}

/// The text elements of an SVG figure (titles, legends, axis labels), one per line.
fn svg_text(path: &Path) -> String {
    let s = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut out = String::new();
    let mut rest = s.as_str();
    while let Some(i) = rest.find("<text") {
        rest = &rest[i..];
        let (Some(open), Some(close)) = (rest.find('>'), rest.find("</text>")) else { break };
        // Axis tick labels (a text that is one number) follow the data's range, which a round-off
        // sensitive curve sets; titles, legends and notes are the figure's statements.
        let text = &rest[open + 1..close];
        let (skeleton, _) = tokens(text.trim());
        if open < close && skeleton != "#" {
            out.push_str(&without_sensitive_notes(text.trim()));
            out.push('\n');
        }
        rest = &rest[close + 7..];
    }
    out
}

/// A figure title without the off-scale notes of round-off sensitive curves ("standard above
/// (round-off sensitive)"): they carry no digit, and whether a chattering curve leaves the panel's
/// range is itself round-off.
fn without_sensitive_notes(line: &str) -> String {
    let Some((head, notes)) = line.split_once("; off-scale: ") else { return line.to_string() };
    let kept: Vec<&str> = notes.split("; ").filter(|n| !n.ends_with("(round-off sensitive)")).collect();
    if kept.is_empty() { head.to_string() } else { format!("{head}; off-scale: {}", kept.join("; ")) }
}

/// Every incompatibility between two `reproduce` folders: report.md and each figure's text.
fn audit(plain: &Path, perturbed: &Path) -> Vec<String> {
    let read = |d: &Path| std::fs::read_to_string(d.join("report.md")).expect("report.md");
    let mut out: Vec<String> =
        incompatible(&read(plain), &read(perturbed)).into_iter().map(|s| format!("report.md {s}")).collect();
    let mut svgs: Vec<PathBuf> = std::fs::read_dir(plain)
        .expect("a reproduce folder")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .collect();
    svgs.sort();
    for p in svgs {
        let name = p.file_name().unwrap();
        for s in incompatible(&svg_text(&p), &svg_text(&perturbed.join(name))) {
            out.push(format!("{} {s}", name.to_string_lossy()));
        }
    }
    out
}

fn reproduce(dir: &Path, audit: bool) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_massredist"));
    c.args(["reproduce", "--quick", "--out"]).arg(dir);
    if audit {
        c.arg("--roundoff-audit");
    }
    let o = c.output().expect("massredist runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn the_comparison_tells_rounding_from_a_changed_digit() {
    // Same words, last digits within rounding: compatible.
    assert!(incompatible("error 0.10415 and 2.3e-5", "error 0.1041 and 2.4e-5").is_empty());
    assert!(incompatible("E = −0.125", "E = −0.1250").is_empty());
    // A changed digit, a changed count, a band where there was a number: not.
    assert_eq!(incompatible("error 0.1041", "error 0.1043").len(), 1);
    assert_eq!(incompatible("mod3 wins in 24 of 30", "mod3 wins in 25 of 30").len(), 1);
    assert_eq!(incompatible("L∞ 0.05", "L∞ 0.37–0.65").len(), 1);
    assert_eq!(incompatible("L∞ 0.010–0.012", "L∞ 0.37–0.65").len(), 1);
    // Bands of round-off sensitive values: overlapping bands, or a number inside the band.
    assert!(incompatible("L∞ 0.26–0.48, E 1.8–2.6", "L∞ 0.28–0.70, E 2.1").is_empty());
    assert!(incompatible("5 runs: bounded–grows", "5 runs: grows").is_empty());
    assert!(incompatible("shift +0.01 to -0.23, then -0.49", "shift -0.02, then −0.49").is_empty());
    assert_eq!(incompatible("5 runs: bounded", "5 runs: grows–diverged").len(), 1);
    assert!(incompatible("stopped at t = varies", "stopped at t = 1500–1621").is_empty());
    // Timing columns of a table are left out.
    let t = |v: &str| format!("| m | err | CPU s |\n|---|---|---|\n| 6 | 0.104 | {v} |");
    assert!(incompatible(&t("0.12"), &t("0.31")).is_empty());
    assert_eq!(incompatible(&t("0.12"), &t("0.31").replace("0.104", "0.107")).len(), 1);
    assert_eq!(incompatible("grows ×2.3", "grows ×982").len(), 1);
    // Words count too; names with digits (fig11, T3, m = 6) are words or exact numbers.
    assert_eq!(incompatible("bounded", "grows").len(), 1);
    assert!(incompatible("fig11-crank-nicolson-T3.png, m = 6", "fig11-crank-nicolson-T3.png, m = 6").is_empty());
    assert_eq!(
        without_sensitive_notes("u_0; off-scale: standard above (round-off sensitive); mod1 min -24.9"),
        "u_0; off-scale: mod1 min -24.9"
    );
    assert_eq!(without_sensitive_notes("u_0; off-scale: standard below (round-off sensitive)"), "u_0");
    let (s, n) = tokens("x1e-3 at −2.5e3, fig12 and 1.30");
    assert_eq!(s, "x1e-3 at #, fig12 and #");
    assert_eq!((n[0].value, n[0].half_unit), (-2500.0, 50.0));
    assert!((n[1].value - 1.3).abs() < 1e-15 && (n[1].half_unit - 0.005).abs() < 1e-15);
}

/// The reduced report and its figures print the same digits when every run starts 1e-13 away.
#[test]
fn a_perturbation_of_1e_13_changes_no_printed_digit() {
    let dirs = std::env::var("MASSREDIST_AUDIT_DIRS").ok();
    let tmp = tempfile::tempdir().unwrap();
    let (plain, perturbed) = match dirs.as_deref().and_then(|d| d.split_once(':')) {
        Some((a, b)) => (PathBuf::from(a), PathBuf::from(b)),
        None => {
            let (a, b) = (tmp.path().join("plain"), tmp.path().join("perturbed"));
            std::thread::scope(|s| {
                s.spawn(|| reproduce(&a, false));
                s.spawn(|| reproduce(&b, true));
            });
            (a, b)
        }
    };
    // The audit changes the numbers at all: the figures' CSVs hold every digit of the series.
    let series = |d: &Path| std::fs::read_to_string(d.join("fig11-crank-nicolson-T3.csv")).unwrap();
    assert_ne!(series(&plain), series(&perturbed), "--roundoff-audit perturbed nothing");
    let bad = audit(&plain, &perturbed);
    assert!(bad.is_empty(), "{} printed numbers change with a 1e-13 perturbation:\n{}", bad.len(), bad.join("\n"));
}
