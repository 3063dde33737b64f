//! The shapes a whole-swarm command's values come in: one value per vehicle or one for all
//! ([`Column`]), or a row-major matrix with one row per vehicle ([`Rows`]), each checked
//! against the number of vehicles commanded.

use super::error::CommandError;

/// One value per row, or one value for every row.
#[derive(Clone, Copy, Debug)]
pub enum Column<'a, T> {
    /// The same value for every row.
    All(T),
    /// One value per row.
    Each(&'a [T]),
}

impl<T: Copy> Column<'_, T> {
    /// The value of row `row`.
    pub fn get(&self, row: usize) -> T {
        match self {
            Self::All(x) => *x,
            Self::Each(xs) => xs[row],
        }
    }

    pub(crate) fn check_len(&self, field: &str, rows: usize) -> Result<(), CommandError> {
        match self {
            Self::Each(xs) if xs.len() != rows => Err(CommandError::field(
                field,
                format!("{} values for {rows} vehicles", xs.len()),
            )),
            _ => Ok(()),
        }
    }
}

/// A row-major matrix: `width` values per row.
#[derive(Clone, Copy, Debug)]
pub struct Rows<'a> {
    /// The values, row after row.
    pub data: &'a [f64],
    /// Values per row.
    pub width: usize,
}

impl Rows<'_> {
    pub(crate) fn row(&self, r: usize) -> &[f64] {
        &self.data[r * self.width..(r + 1) * self.width]
    }

    pub(crate) fn check_len(&self, field: &str, rows: usize) -> Result<(), CommandError> {
        if self.data.len() != rows * self.width {
            return Err(CommandError::field(
                field,
                format!(
                    "{} values for {rows} vehicles × {} columns",
                    self.data.len(),
                    self.width
                ),
            ));
        }
        Ok(())
    }
}
