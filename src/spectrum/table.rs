//! The plain-text spectral table format of `spectra/` and of user spectrum files.
//!
//! ```text
//! # comment lines (source, units)
//! nm x y z          <- header: "nm" then one name per value column
//! 360 0.0001299 3.917e-06 0.0006061
//! ```
//! Wavelengths in nm, strictly increasing; values finite. Blank lines and `#` lines are skipped;
//! a file without a header line is read as `nm value`.
//!
//! This file has no dependencies beyond `std` because `build.rs` includes it too (it embeds the
//! data files and fits the RGB uplifting table at build time).

use std::fmt;

/// A parsed table: one wavelength column and one or more named value columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub columns: Vec<String>,
    pub wavelengths: Vec<f64>,
    /// `values[c][i]` is column `c` at `wavelengths[i]`.
    pub values: Vec<Vec<f64>>,
}

/// What is wrong with a table, and where (1-based line).
#[derive(Debug, Clone, PartialEq)]
pub struct TableError {
    pub line: usize,
    pub message: String,
}

impl fmt::Display for TableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for TableError {}

impl Table {
    /// The values of the column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .position(|c| c == name)
            .map(|i| self.values[i].as_slice())
    }

    /// Linear interpolation of column `c` at `nm`; 0 outside the tabulated range.
    pub fn interpolate(&self, c: usize, nm: f64) -> f64 {
        let wl = &self.wavelengths;
        let v = &self.values[c];
        if wl.is_empty() || nm < wl[0] || nm > wl[wl.len() - 1] {
            return 0.0;
        }
        let i = wl.partition_point(|&w| w <= nm).clamp(1, wl.len() - 1);
        let (w0, w1) = (wl[i - 1], wl[i]);
        let t = if w1 > w0 { (nm - w0) / (w1 - w0) } else { 0.0 };
        v[i - 1] + t * (v[i] - v[i - 1])
    }
}

/// Parses the text of a table.
pub fn parse(text: &str) -> Result<Table, TableError> {
    let mut columns: Option<Vec<String>> = None;
    let mut wavelengths = Vec::new();
    let mut values: Vec<Vec<f64>> = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line_no = index + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|f| !f.is_empty())
            .collect();
        let err = |message: String| TableError {
            line: line_no,
            message,
        };
        // Separators only (`,`, `;`): no field to read (fuzz finding, seed 14 case 1464: it
        // indexed an empty list).
        if fields.is_empty() {
            return Err(err(format!(
                "the line `{line}` has separators but no numbers"
            )));
        }
        if columns.is_none() {
            if fields[0].parse::<f64>().is_err() {
                if fields.len() < 2 {
                    return Err(err(
                        "the header needs `nm` and at least one column name".into()
                    ));
                }
                columns = Some(fields[1..].iter().map(|s| s.to_string()).collect());
                values = vec![Vec::new(); fields.len() - 1];
                continue;
            }
            columns = Some(vec!["value".to_string()]);
            values = vec![Vec::new()];
        }
        let ncol = values.len();
        if fields.len() != ncol + 1 {
            return Err(err(format!(
                "expected {} numbers (nm and {} value column{}), found {}",
                ncol + 1,
                ncol,
                if ncol == 1 { "" } else { "s" },
                fields.len()
            )));
        }
        let mut nums = Vec::with_capacity(fields.len());
        for f in &fields {
            match f.parse::<f64>() {
                Ok(x) if x.is_finite() => nums.push(x),
                Ok(_) => return Err(err(format!("`{f}` is not a finite number"))),
                Err(_) => return Err(err(format!("`{f}` is not a number"))),
            }
        }
        if let Some(&last) = wavelengths.last() {
            if nums[0] <= last {
                return Err(err(format!(
                    "wavelengths must increase strictly: {} nm follows {} nm",
                    nums[0], last
                )));
            }
        }
        if nums[0] <= 0.0 {
            return Err(err(format!("wavelength {} nm is not positive", nums[0])));
        }
        wavelengths.push(nums[0]);
        for (c, v) in nums[1..].iter().enumerate() {
            values[c].push(*v);
        }
    }
    let columns = columns.ok_or(TableError {
        line: 0,
        message: "the table has no rows".into(),
    })?;
    if wavelengths.is_empty() {
        return Err(TableError {
            line: 0,
            message: "the table has no rows".into(),
        });
    }
    Ok(Table {
        columns,
        wavelengths,
        values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_header_and_rows() {
        let t = parse("# c\nnm a b\n400 1 2\n410 3 4\n").unwrap();
        assert_eq!(t.columns, vec!["a", "b"]);
        assert_eq!(t.wavelengths, vec![400.0, 410.0]);
        assert_eq!(t.column("b").unwrap(), &[2.0, 4.0]);
        assert!((t.interpolate(0, 405.0) - 2.0).abs() < 1e-12);
        assert_eq!(t.interpolate(0, 399.0), 0.0);
    }

    #[test]
    fn headerless_is_value_column() {
        let t = parse("400, 0.5\n500, 0.25\n").unwrap();
        assert_eq!(t.columns, vec!["value"]);
    }

    #[test]
    fn rejects_bad_rows() {
        assert_eq!(parse("nm v\n400 1\n390 2\n").unwrap_err().line, 3);
        assert_eq!(parse("nm v\n400 nan\n").unwrap_err().line, 2);
        assert_eq!(parse("nm v\n400 1 2\n").unwrap_err().line, 2);
        assert!(parse("# only comments\n").is_err());
    }
}
