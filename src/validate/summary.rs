//! What `prisma validate` says while and after it runs, as text: one progress line per case
//! (`[k/N] NAME … PASS (time)`) with an estimate of the time left, the result table with a
//! header and aligned columns, its closing line `validate: N passed, M failed`, and the overall
//! verdict that heads the table and the reports. Pure functions of the results and the times
//! measured; the command decides where and whether to print them.

use super::{CaseResult, Kind};

/// The verdict printed on the line `PASS`/`FAIL` of a check or a case.
pub fn verdict_word(passed: bool) -> &'static str {
    if passed {
        "PASS"
    } else {
        "FAIL"
    }
}

/// Seconds as a person reads them: `< 0.01 s`, `0.42 s`, `12.3 s`, `48 s`, `3 min 05 s`, `1 h 02 min`.
pub fn duration(seconds: f64) -> String {
    if !seconds.is_finite() || seconds < 0.0 {
        return "?".to_owned();
    }
    if seconds < 0.005 {
        // Not "0.00 s": the case did run.
        return "< 0.01 s".to_owned();
    }
    if seconds < 1.0 {
        return format!("{seconds:.2} s");
    }
    if seconds < 10.0 {
        return format!("{seconds:.1} s");
    }
    let whole = seconds.round() as u64;
    match whole {
        0..60 => format!("{whole} s"),
        60..3600 => format!("{} min {:02} s", whole / 60, whole % 60),
        _ => format!("{} h {:02} min", whole / 3600, whole / 60 % 60),
    }
}

/// A value or a threshold in the tables: four decimals and a signed two-digit exponent,
/// `2.2120e+00`, `3.0864e-03`, so that numbers of one column line up digit for digit.
pub fn scientific(value: f64) -> String {
    let text = format!("{value:.4e}");
    match text.split_once('e') {
        Some((mantissa, exponent)) => {
            let (sign, digits) = exponent.strip_prefix('-').map_or(("+", exponent), |d| ("-", d));
            format!("{mantissa}e{sign}{digits:0>2}")
        }
        // NaN and infinities have no exponent.
        None => text,
    }
}

/// The line of case `index` (from 0) of `total`, padded so that the verdicts of every line
/// stand in one column when `name_width` is the longest name: `[ 3/49] dispersion_450 …` while
/// it runs, `[ 3/49] dispersion_450 … PASS (2.1 s)` when it has run in `seconds`.
pub fn progress_line(
    index: usize,
    total: usize,
    name: &str,
    name_width: usize,
    ran: Option<(bool, f64)>,
) -> String {
    let digits = total.to_string().len();
    let head = format!("[{:>digits$}/{total}] {name:<name_width$} …", index + 1);
    match ran {
        None => head,
        Some((passed, seconds)) => format!("{head} {} ({})", verdict_word(passed), duration(seconds)),
    }
}

/// The time the cases still to run (`remaining`, by kind) should take, in seconds, from the
/// cases done (`done`: kind and seconds): each remaining case is counted at the mean time of
/// the cases done of its kind, or of its class when none of its kind is done (an analytic case
/// takes milliseconds, a case that renders images seconds or minutes, so neither says much
/// about the other). `None` until every remaining case has such a mean.
pub fn time_left(done: &[(Kind, f64)], remaining: &[Kind]) -> Option<f64> {
    let mean = |same: &dyn Fn(Kind) -> bool| {
        let times: Vec<f64> = done.iter().filter(|(kind, _)| same(*kind)).map(|&(_, s)| s).collect();
        (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64)
    };
    remaining
        .iter()
        .map(|&kind| {
            mean(&|other| other == kind)
                .or_else(|| mean(&|other| other.compares_images() == kind.compares_images()))
        })
        .sum()
}

/// Seconds to the nearest whole second, for times that change while a person watches them:
/// `12 s`, `3 min 05 s`, `1 h 02 min`.
pub fn whole_seconds(seconds: f64) -> String {
    if seconds.is_finite() && (0.0..59.5).contains(&seconds) {
        format!("{} s", seconds.round())
    } else {
        duration(seconds)
    }
}

/// What the running line of a terminal says after its `[k/N] NAME …`: the case's time so far
/// and, once known, the time left, `12 s, about 3 min 05 s left`. `current` is the time the
/// running case should take, `rest` the time of the cases after it ([`time_left`] of each), so
/// that the estimate counts down while the case runs and stops at `rest` when the case runs
/// longer than expected.
pub fn running_note(elapsed: f64, current: Option<f64>, rest: Option<f64>) -> String {
    let so_far = whole_seconds(elapsed);
    match current.zip(rest).map(|(current, rest)| rest + (current - elapsed).max(0.0)) {
        Some(left) if left >= 0.5 => format!("{so_far}, about {} left", whole_seconds(left)),
        _ => so_far,
    }
}

/// The overall outcome of a run: how many cases ran and which failed, in the order they ran.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Verdict {
    /// Cases run.
    pub total: usize,
    /// Names of the cases that failed.
    pub failed: Vec<String>,
}

impl Verdict {
    /// The verdict of `results`.
    pub fn of<'a>(results: impl IntoIterator<Item = &'a CaseResult>) -> Self {
        let (mut total, mut failed) = (0, Vec::new());
        for result in results {
            total += 1;
            if !result.passed() {
                failed.push(result.name.clone());
            }
        }
        Verdict { total, failed }
    }

    /// True when at least one case ran and none failed.
    pub fn passed(&self) -> bool {
        self.total > 0 && self.failed.is_empty()
    }

    /// The verdict in words, without the names: `all 49 cases passed`, `2 of 49 cases failed`.
    pub fn headline(&self) -> String {
        let cases = |n: usize| if n == 1 { "case" } else { "cases" };
        match (self.total, self.failed.len()) {
            (0, _) => "no case ran".to_owned(),
            (1, 0) => "the case passed".to_owned(),
            (total, 0) => format!("all {total} {} passed", cases(total)),
            (total, failed) => format!("{failed} of {total} {} failed", cases(total)),
        }
    }

    /// The closing line of the table: `validate: 47 passed, 2 failed`.
    pub fn summary_line(&self) -> String {
        format!("validate: {} passed, {} failed", self.total - self.failed.len(), self.failed.len())
    }
}

/// The headers of the result table, in order.
pub const TABLE_HEADER: [&str; 6] = ["case", "kind", "metric", "value", "threshold", "result"];

/// The result table: a header row, one row per check (a case without checks gets one row, and
/// fails), columns as wide as their widest cell (text left-aligned, numbers right-aligned, in
/// the format of [`scientific`]), then [`Verdict::summary_line`].
pub fn table(results: &[(&CaseResult, Kind)]) -> String {
    let mut rows: Vec<[String; 6]> = Vec::new();
    for (result, kind) in results {
        let row = |metric: &str, value: String, threshold: String, passed: bool| {
            [
                result.name.clone(),
                kind.label().to_owned(),
                metric.to_owned(),
                value,
                threshold,
                verdict_word(passed).to_owned(),
            ]
        };
        if result.checks.is_empty() {
            rows.push(row("(no checks)", "-".to_owned(), "-".to_owned(), false));
        }
        for check in &result.checks {
            rows.push(row(
                &check.metric,
                scientific(check.value),
                scientific(check.threshold),
                check.passed(),
            ));
        }
    }
    let header = TABLE_HEADER.map(str::to_owned);
    let mut widths = [0; 6];
    for row in std::iter::once(&header).chain(&rows) {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.chars().count());
        }
    }
    let mut text = String::new();
    for row in std::iter::once(&header).chain(&rows) {
        let cells: Vec<String> = row
            .iter()
            .zip(widths)
            .enumerate()
            .map(|(column, (cell, width))| match column {
                // value and threshold: numbers, right-aligned so that exponents line up.
                3 | 4 => format!("{cell:>width$}"),
                _ => format!("{cell:<width$}"),
            })
            .collect();
        text.push_str(cells.join("  ").trim_end());
        text.push('\n');
    }
    text.push_str(&Verdict::of(results.iter().map(|(r, _)| *r)).summary_line());
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::Check;

    fn case(name: &str, values: &[f64]) -> CaseResult {
        CaseResult {
            name: name.to_owned(),
            checks: values
                .iter()
                .map(|&value| Check { metric: "relMSE".to_owned(), value, threshold: 1e-3 })
                .collect(),
            why: String::new(),
        }
    }

    #[test]
    fn durations_read_as_people_say_them() {
        assert_eq!(duration(0.0004), "< 0.01 s");
        assert_eq!(duration(0.4213), "0.42 s");
        assert_eq!(duration(2.14), "2.1 s");
        assert_eq!(duration(48.4), "48 s");
        assert_eq!(duration(185.0), "3 min 05 s");
        assert_eq!(duration(3720.0), "1 h 02 min");
        assert_eq!(duration(f64::NAN), "?");
    }

    #[test]
    fn numbers_have_one_width() {
        assert_eq!(scientific(2.212), "2.2120e+00");
        assert_eq!(scientific(3.0864e-3), "3.0864e-03");
        assert_eq!(scientific(-1.5e-12), "-1.5000e-12");
        assert_eq!(scientific(1e100), "1.0000e+100");
        assert_eq!(scientific(f64::NAN), "NaN");
        assert_eq!(scientific(f64::INFINITY), "inf");
    }

    #[test]
    fn progress_lines_keep_their_verdicts_in_one_column() {
        // Nine of twelve: the index is padded to the width of the total, the name to the widest.
        let running = progress_line(8, 12, "snell_window", 14, None);
        assert_eq!(running, "[ 9/12] snell_window   …");
        let done = progress_line(8, 12, "snell_window", 14, Some((true, 2.14)));
        assert_eq!(done, "[ 9/12] snell_window   … PASS (2.1 s)");
        let other = progress_line(11, 12, "dispersion_450", 14, Some((false, 48.0)));
        assert_eq!(other, "[12/12] dispersion_450 … FAIL (48 s)");
        assert_eq!(done.find("PASS"), other.find("FAIL"));
    }

    #[test]
    fn time_left_counts_each_case_at_the_mean_of_its_kind() {
        let done = [(Kind::Analytic, 1.0), (Kind::Analytic, 3.0), (Kind::Mitsuba, 20.0)];
        // Two analytic cases at 2 s, one Mitsuba case at 20 s.
        assert_eq!(time_left(&done, &[Kind::Analytic, Kind::Analytic, Kind::Mitsuba]), Some(24.0));
        // No polarised Mitsuba case done yet: counted as the image cases done (20 s).
        assert_eq!(time_left(&done, &[Kind::MitsubaPolarised]), Some(20.0));
        // Analytic cases say nothing about image cases: no estimate yet.
        assert_eq!(time_left(&done[..2], &[Kind::Analytic, Kind::Mitsuba]), None);
        assert_eq!(time_left(&[], &[Kind::Analytic]), None);
        // Nothing left.
        assert_eq!(time_left(&done, &[]), Some(0.0));
    }

    #[test]
    fn the_running_note_counts_down_to_the_cases_after() {
        // A case expected to take 20 s, 165 s of cases after it.
        assert_eq!(running_note(0.2, Some(20.0), Some(165.0)), "0 s, about 3 min 05 s left");
        assert_eq!(running_note(12.4, Some(20.0), Some(30.0)), "12 s, about 38 s left");
        // Longer than expected: what is left is the cases after it.
        assert_eq!(running_note(95.0, Some(20.0), Some(30.0)), "1 min 35 s, about 30 s left");
        // The last case, and a case whose kind has no time yet.
        assert_eq!(running_note(3.0, Some(5.0), Some(0.0)), "3 s, about 2 s left");
        assert_eq!(running_note(7.0, Some(5.0), Some(0.0)), "7 s");
        assert_eq!(running_note(3.0, None, Some(10.0)), "3 s");
    }

    #[test]
    fn verdicts_name_the_failures() {
        let (pass, fail) = (case("furnace_glass", &[1e-4]), case("tp6_quad", &[1e-4, 2e-3]));
        let all = Verdict::of([&pass, &pass]);
        assert!(all.passed());
        assert_eq!(all.headline(), "all 2 cases passed");
        let some = Verdict::of([&pass, &fail]);
        assert!(!some.passed());
        assert_eq!(some.failed, ["tp6_quad"]);
        assert_eq!(some.headline(), "1 of 2 cases failed");
        assert_eq!(some.summary_line(), "validate: 1 passed, 1 failed");
        assert_eq!(Verdict::of([]).headline(), "no case ran");
        // A case without checks has shown nothing: it fails.
        assert!(!Verdict::of([&case("empty", &[])]).passed());
    }

    #[test]
    fn the_table_has_a_header_aligned_columns_and_a_summary_line() {
        let (pass, fail) = (case("furnace_glass", &[2.08e-8]), case("tp6_quad", &[1e-4, 2e-3]));
        let text = table(&[(&pass, Kind::Analytic), (&fail, Kind::Mitsuba)]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 5, "{text}");
        assert!(lines[0].starts_with("case") && lines[0].ends_with("result"), "{text}");
        assert_eq!(lines[4], "validate: 1 passed, 1 failed");
        // Every column starts where its header does; numbers end where theirs do.
        for (row, expected) in lines[1..4].iter().zip([
            ["furnace_glass", "analytic", "relMSE", "2.0800e-08", "1.0000e-03", "PASS"],
            ["tp6_quad", "Mitsuba", "relMSE", "1.0000e-04", "1.0000e-03", "PASS"],
            ["tp6_quad", "Mitsuba", "relMSE", "2.0000e-03", "1.0000e-03", "FAIL"],
        ]) {
            for (column, (cell, header)) in expected.iter().zip(TABLE_HEADER).enumerate() {
                let at = lines[0].find(header).unwrap();
                let found = match column {
                    3 | 4 => row[..at + header.len()].ends_with(cell),
                    _ => row[at..].starts_with(cell),
                };
                assert!(found, "{cell} not under {header}:\n{text}");
            }
        }
    }
}
