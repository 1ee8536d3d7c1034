//! Verity's comparison side: metrics, studies and reports (to come), and the `verity`
//! command-line tool ([`cli`]; reference in compare/README.md).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod mitsuba;
pub mod progress;
