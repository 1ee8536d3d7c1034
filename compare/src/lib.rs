//! Verity's comparison side: [`metrics`], [`study`] files and their runs, the [`report`], the
//! Mitsuba 3 cross-check, and the `verity` command-line tool ([`cli`]; reference in
//! compare/README.md).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod colormap;
pub mod diff;
pub mod input;
pub mod markup;
pub mod metrics;
pub mod mitsuba;
pub mod progress;
pub mod report;
pub mod stats;
pub mod study;
