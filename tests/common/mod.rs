//! Shared by the fixture tests: reading Mitsuba's CSV fixtures and comparing prisma with them
//! row by row.

use std::path::Path;

/// The rows of a fixture whose column header is `columns` (lines starting with `#` skipped), as
/// numbers.
pub fn read_fixture(name: &str, columns: &str) -> Vec<Vec<f32>> {
    read_fixture_fields(name, columns, 0).into_iter().map(|(_, numbers)| numbers).collect()
}

/// The rows of a fixture whose first `text_columns` columns are text: (text fields, numbers).
pub fn read_fixture_fields(name: &str, columns: &str, text_columns: usize) -> Vec<(Vec<String>, Vec<f32>)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|err| {
        panic!(
            "{}: {err}; regenerate it with the script under validation/mitsuba/ that names it",
            path.display()
        )
    });
    let mut lines = text.lines().enumerate().filter(|(_, line)| !line.starts_with('#'));
    let (_, header) = lines.next().unwrap_or_else(|| panic!("{name}: no column header"));
    assert_eq!(header, columns, "{name}: unexpected columns");
    let width = columns.split(',').count();
    lines
        .map(|(index, line)| {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), width, "{name}:{}: {line:?}", index + 1);
            let numbers = fields[text_columns..]
                .iter()
                .map(|field| {
                    field.parse().unwrap_or_else(|err| panic!("{name}:{}: {err} in {line:?}", index + 1))
                })
                .collect();
            (fields[..text_columns].iter().map(|f| f.to_string()).collect(), numbers)
        })
        .collect()
}

/// The largest difference seen for one quantity, and where.
struct Worst {
    quantity: &'static str,
    difference: f32,
    context: String,
}

/// Collects differences between prisma and Mitsuba and fails on any beyond `tolerance`.
pub struct Comparison {
    tolerance: f32,
    worst: Vec<Worst>,
    failures: Vec<String>,
    /// Rows compared.
    pub rows: usize,
}

impl Comparison {
    /// An empty comparison failing on absolute differences beyond `tolerance`.
    pub fn new(tolerance: f32) -> Self {
        Self { tolerance, worst: Vec::new(), failures: Vec::new(), rows: 0 }
    }

    /// Records one quantity of one row.
    pub fn check(&mut self, quantity: &'static str, prisma: f32, mitsuba: f32, context: &str) {
        let difference = (prisma - mitsuba).abs();
        // NaN in either makes `difference` NaN, which must fail too.
        if difference.is_nan() || difference > self.tolerance {
            self.failures.push(format!("{quantity}: prisma {prisma} vs Mitsuba {mitsuba} at {context}"));
        }
        match self.worst.iter_mut().find(|w| w.quantity == quantity) {
            Some(worst) if difference.is_nan() || difference > worst.difference => {
                worst.difference = difference;
                worst.context = context.to_owned();
            }
            Some(_) => {}
            None => self.worst.push(Worst { quantity, difference, context: context.to_owned() }),
        }
    }

    /// Prints the largest difference of each quantity and fails if any row was beyond tolerance.
    pub fn finish(self, fixture: &str) {
        let tolerance = self.tolerance;
        println!("{fixture}: {} rows compared, tolerance {tolerance:e}", self.rows);
        for worst in &self.worst {
            println!("  max |Δ{}| = {:.3e} at {}", worst.quantity, worst.difference, worst.context);
        }
        assert!(self.rows > 0, "{fixture}: no rows");
        assert!(
            self.failures.is_empty(),
            "{fixture}: {} differences beyond {tolerance:e}, first ones:\n{}",
            self.failures.len(),
            self.failures.iter().take(20).cloned().collect::<Vec<_>>().join("\n")
        );
    }
}
