//! What a run produces: the [`ResultTable`] of recorded variables and the [`Stats`] of the
//! stepping.

use std::fmt::Write as _;

/// Time and the recorded variables at every communication point (the start time included).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ResultTable {
    columns: Vec<String>,
    time: Vec<f64>,
    data: Vec<Vec<f64>>,
}

impl ResultTable {
    pub(crate) fn new(columns: Vec<String>) -> ResultTable {
        let data = vec![Vec::new(); columns.len()];
        ResultTable {
            columns,
            time: Vec::new(),
            data,
        }
    }

    pub(crate) fn push(&mut self, time: f64, row: &[f64]) {
        debug_assert_eq!(row.len(), self.columns.len());
        self.time.push(time);
        for (column, &value) in self.data.iter_mut().zip(row) {
            column.push(value);
        }
    }

    /// The recorded variables, `"instance.variable"`, in the order asked for.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    pub fn time(&self) -> &[f64] {
        &self.time
    }

    /// The values of one recorded variable (Integer and Boolean ones as 0/1 `f64`).
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .position(|c| c == name)
            .map(|i| self.data[i].as_slice())
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// The table as CSV: a header `time,<columns>` and one line per row.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("time");
        for c in &self.columns {
            out.push(',');
            out.push_str(c);
        }
        out.push('\n');
        for (row, t) in self.time.iter().enumerate() {
            let _ = write!(out, "{t}");
            for column in &self.data {
                let _ = write!(out, ",{}", column[row]);
            }
            out.push('\n');
        }
        out
    }
}

/// Counters of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Communication steps completed (rows of the table minus one).
    pub communication_steps: usize,
    /// Macro steps accepted; more than `communication_steps` when error control divided some.
    pub accepted_steps: usize,
    /// Macro steps rejected by error control (states restored, step halved).
    pub rejected_steps: usize,
    /// Steps accepted at the minimum step size although their error estimate exceeded the
    /// tolerance.
    pub accepted_over_tolerance: usize,
    /// The smallest macro step taken, s.
    pub smallest_step: f64,
    /// The largest coupling error estimate of an accepted step (relative, see
    /// [`super::ErrorControl`]); computed with or without error control.
    pub largest_error_estimate: f64,
    /// Calls of `fmi2DoStep`, every instance together.
    pub do_step_calls: usize,
}
