//! The one CSV writer of the results folders (`identify.csv`, `configs.csv`, ...): fields are
//! quoted by the `csv` crate where RFC 4180 needs it (a comma, a quote or a line break in
//! them), records end in `\n`, and every record has the header's width.
//!
//! A [`Cell`] is either [`text`], guarded against spreadsheet formulas, or a [`value`] (a
//! number, a count, a flag) written as it displays. Ordinary names and numbers therefore come
//! out as plain `a,b,c` lines, the same bytes a `format!` of them gives.

use std::fmt::Display;

use crate::error::LabError;

/// One cell of a [`CsvTable`] record: made by [`text`], [`value`], [`fixed`] or
/// [`Cell::empty`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cell {
    content: String,
}

impl Cell {
    /// An empty cell (a value that is not there).
    pub fn empty() -> Self {
        Self {
            content: String::new(),
        }
    }

    /// The cell's content, as it is written before any quoting.
    pub fn as_str(&self) -> &str {
        &self.content
    }
}

/// The characters that make a spreadsheet read a cell as a formula when the cell starts with
/// one (OWASP's CSV injection list: `=`, `+`, `-`, `@`, tab and carriage return).
const FORMULA_STARTS: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// A text cell (a wire's name, an outcome, a label): `text` itself, or behind a `'` when it
/// starts with one of `= + - @`, a tab or a carriage return, so that a spreadsheet shows it as
/// text instead of evaluating it.
///
/// # Example
/// ```
/// use ftwire_app::csv_table::text;
/// assert_eq!(text("nitinol-2mm-630").as_str(), "nitinol-2mm-630");
/// assert_eq!(text("=HYPERLINK(\"x\")").as_str(), "'=HYPERLINK(\"x\")");
/// assert_eq!(text("-0.5").as_str(), "'-0.5", "text that looks like a number is still text");
/// ```
pub fn text(text: &str) -> Cell {
    let content = if text.starts_with(FORMULA_STARTS) {
        format!("'{text}")
    } else {
        text.to_owned()
    };
    Cell { content }
}

/// What a [`value`] cell holds: numbers, counts and flags, written as they display (`-0.5`,
/// `NaN`, `12`, `true`) and never guarded, a leading minus sign being the number's.
pub trait Plain: Display {}

impl Plain for f64 {}
impl Plain for usize {}
impl Plain for u64 {}
impl Plain for i64 {}
impl Plain for bool {}

/// A number, count or flag cell, as it displays.
///
/// # Example
/// ```
/// use ftwire_app::csv_table::value;
/// assert_eq!(value(-0.5).as_str(), "-0.5");
/// assert_eq!(value(3_usize).as_str(), "3");
/// assert_eq!(value(true).as_str(), "true");
/// ```
pub fn value(value: impl Plain) -> Cell {
    Cell {
        content: value.to_string(),
    }
}

/// A number cell with `digits` decimals (`fixed(0.12345, 3)` is `0.123`).
pub fn fixed(value: f64, digits: usize) -> Cell {
    Cell {
        content: format!("{value:.digits$}"),
    }
}

/// A CSV file being built in memory: a header row, then records of the same width.
#[derive(Debug)]
pub struct CsvTable {
    /// The file's name, for errors.
    name: String,
    /// Cells per record.
    width: usize,
    /// The header, then the records.
    writer: csv::Writer<Vec<u8>>,
}

impl CsvTable {
    /// A table for the file `name` whose header row is `columns`.
    ///
    /// # Errors
    /// As [`CsvTable::row`].
    ///
    /// # Example
    /// ```
    /// use ftwire_app::csv_table::{CsvTable, text, value};
    /// let mut table = CsvTable::new("wires.csv", &["wire", "error"])?;
    /// table.row([text("a,b"), value(-0.5)])?;
    /// table.row([text("=1+2"), value(f64::NAN)])?;
    /// assert_eq!(table.into_bytes()?, b"wire,error\n\"a,b\",-0.5\n'=1+2,NaN\n");
    /// # Ok::<(), ftwire_app::error::LabError>(())
    /// ```
    pub fn new(name: &str, columns: &[&str]) -> Result<Self, LabError> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        writer
            .write_record(columns)
            .map_err(|e| LabError::io(format!("writing {name}"), e.into()))?;
        Ok(Self {
            name: name.to_owned(),
            width: columns.len(),
            writer,
        })
    }

    /// Appends one record.
    ///
    /// # Errors
    /// [`LabError::Io`] when the record's width is not the header's (a bug of the caller).
    pub fn row(&mut self, cells: impl IntoIterator<Item = Cell>) -> Result<(), LabError> {
        let cells: Vec<Cell> = cells.into_iter().collect();
        let error = |e: std::io::Error| LabError::io(format!("writing {}", self.name), e);
        if cells.len() != self.width {
            return Err(error(std::io::Error::other(format!(
                "a record of {} cells under a header of {}",
                cells.len(),
                self.width
            ))));
        }
        self.writer
            .write_record(cells.iter().map(Cell::as_str))
            .map_err(|e| error(e.into()))
    }

    /// The file's bytes.
    ///
    /// # Errors
    /// [`LabError::Io`] if the last record cannot be written.
    pub fn into_bytes(self) -> Result<Vec<u8>, LabError> {
        let name = self.name;
        self.writer
            .into_inner()
            .map_err(|e| LabError::io(format!("writing {name}"), e.into_error()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hostile_text_is_quoted_and_guarded_and_numbers_are_not() {
        let name = "=1+2,\"evil\"\n<script>x</script>";
        let mut table = CsvTable::new("t.csv", &["wire", "x", "ok"]).expect("a header");
        table
            .row([text(name), value(-0.25), value(false)])
            .expect("a row");
        table
            .row([text("@SUM(A1)"), value(1e-7), Cell::empty()])
            .expect("a row");
        let bytes = table.into_bytes().expect("bytes");
        assert_eq!(
            String::from_utf8_lossy(&bytes),
            "wire,x,ok\n\"'=1+2,\"\"evil\"\"\n<script>x</script>\",-0.25,false\n\
             '@SUM(A1),0.0000001,\n"
        );
        let mut reader = csv::Reader::from_reader(bytes.as_slice());
        let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("a record")).collect();
        assert_eq!(rows.len(), 2);
        assert_eq!(&rows[0][0], format!("'{name}"));
        assert_eq!(&rows[0][1], "-0.25");
    }

    #[test]
    fn fixed_numbers_keep_their_decimals() {
        let mut table = CsvTable::new("p.csv", &["mean_mm", "outcome"]).expect("a header");
        table
            .row([fixed(f64::NAN, 3), text("reached")])
            .expect("a row");
        table
            .row([fixed(-1.23456, 3), text("refused at waypoint 3: a, b")])
            .expect("a row");
        assert_eq!(
            table.into_bytes().expect("bytes"),
            b"mean_mm,outcome\nNaN,reached\n-1.235,\"refused at waypoint 3: a, b\"\n"
        );
    }

    #[test]
    fn a_record_of_another_width_is_an_error() {
        let mut table = CsvTable::new("t.csv", &["a", "b"]).expect("a header");
        let e = table.row([value(1_usize)]).expect_err("too short");
        assert!(e.to_string().contains("t.csv"), "{e}");
    }
}
