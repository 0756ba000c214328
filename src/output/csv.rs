//! The CSV files of a run, from the tables the study kinds own
//! ([`crate::studies::StudyResult::tables`]): the tables of every study that writes to one file,
//! appended in scene order under one header. `curves.csv` (uniaxial curves and cylinder sweeps,
//! one row per point, long "tidy" form) comes first; like every file, it is written only
//! when a study writes to it. A cell that does not apply is empty, never `NaN`; a non-finite number is an error
//! naming the file, the column and the row.

use super::datapackage::{table_fields, Resource};
use crate::app_error::AppError;
use crate::scene::Results;
use crate::studies::table::Table;
use crate::studies::table::CURVES_FILE;

/// One CSV file of a run: the tables of the studies that write to it, in scene order.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvFile {
    /// The file name, relative to the output directory.
    pub file: String,
    /// What one row is.
    pub rows_are: &'static str,
    /// One table per study (at least one; all with the same columns).
    pub tables: Vec<Table>,
}

impl CsvFile {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.tables.iter().map(Table::rows).sum()
    }

    /// The header: the columns' names.
    pub fn columns(&self) -> Vec<&'static str> {
        self.tables.first().map(Table::names).unwrap_or_default()
    }

    /// The CSV text.
    pub fn bytes(&self) -> Result<Vec<u8>, AppError> {
        let tables: Vec<&Table> = self.tables.iter().collect();
        table_csv(&self.file, &tables)
    }

    /// Its schema for `datapackage.json`.
    pub fn resource(&self) -> Resource {
        Resource {
            path: self.file.clone(),
            description: self.rows_are.to_string(),
            fields: self.tables.first().map(table_fields).unwrap_or_default(),
        }
    }
}

/// The CSV files of `results`, each with at least one row-holding study: `curves.csv` first if
/// a study writes to it, then the others in the order of the first study that writes to each. A
/// scene without uniaxial or cylinder studies has no `curves.csv` (a header alone says nothing).
pub fn files(results: &Results) -> Vec<CsvFile> {
    let mut files: Vec<CsvFile> = Vec::new();
    let own = results
        .studies
        .iter()
        .flat_map(|s| s.result.tables(&s.name));
    for t in own {
        match files.iter_mut().find(|f| f.file == t.file) {
            Some(f) => f.tables.push(t.table),
            None => files.push(CsvFile {
                file: t.file,
                rows_are: t.rows_are,
                tables: vec![t.table],
            }),
        }
    }
    // A stable sort: curves.csv first, the others keep their order.
    files.sort_by_key(|f| f.file != CURVES_FILE);
    files
}

fn csv_error(file: &str) -> impl Fn(csv::Error) -> AppError + '_ {
    move |e| AppError::Output {
        file: file.to_string(),
        message: e.to_string(),
    }
}

/// The CSV text of tables with the same columns (the tables of the studies that write to
/// `file`), the header once; empty cells for `None`; numbers in their shortest exact form
/// ([`crate::text::shortest`]). A non-finite number is an error naming the file, the column
/// and the row ([`Table::check_from`]); tables with other columns than the first's are an error.
pub fn table_csv(file: &str, tables: &[&Table]) -> Result<Vec<u8>, AppError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error(file);
    if let Some(first) = tables.first() {
        w.write_record(first.names()).map_err(&fail)?;
    }
    let mut before = 0;
    for t in tables {
        if !t.same_columns(tables[0]) {
            return Err(AppError::Output {
                file: file.to_string(),
                message: format!(
                    "the tables written to one file differ: {:?} and {:?}",
                    tables[0].names(),
                    t.names()
                ),
            });
        }
        t.check_from(file, before)?;
        for row in 0..t.rows() {
            w.write_record(t.columns.iter().map(|c| c.cell(row)))
                .map_err(&fail)?;
        }
        before += t.rows();
    }
    w.into_inner().map_err(|e| AppError::Output {
        file: file.to_string(),
        message: e.error().to_string(),
    })
}

/// `x` with the fewest digits that read back to the same f64: [`crate::text::shortest`].
pub fn shortest(x: f64) -> String {
    crate::text::shortest(x)
}

#[cfg(test)]
mod tests {
    use super::shortest;

    #[test]
    fn numbers_read_back_exactly_and_stay_short_at_every_magnitude() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -1.25,
            1e-4,
            9.99e-5,
            1e15,
            9.99e14,
            2.85e266,
            -3.8e-100,
            8.128632865720501e-75,
            6.16e-16,
            f64::MIN_POSITIVE,
            f64::MAX,
            5e-324,
        ];
        // A deterministic spread of magnitudes and mantissas.
        let mut x = 0.123_456_789_f64;
        for k in -300..300 {
            x = (x * 997.0 + 0.317).fract();
            values.push((x + 0.01) * 10f64.powi(k));
        }
        assert_eq!(shortest(-0.0), "0");
        for v in values {
            let s = shortest(v);
            assert_eq!(s.parse::<f64>().ok(), Some(v), "{v:e} written as {s}");
            assert!(
                s.len() <= 25,
                "{v:e} written as {s} ({} characters)",
                s.len()
            );
        }
    }
}
