//! The Mitsuba 3 cross-check (docs/ARCHITECTURE.md "Comparison"): export a scene to Mitsuba 3, render it
//! with Mitsuba through the project's Python venv, and test per pixel that the oracle and
//! Mitsuba converge to the same image.
//!
//! - [`export`]: scene model → Mitsuba XML (+ PLY, EXR), exact or refused.
//! - [`ztest`]: the per-pixel z-test of Mitsuba's own render tests, and relMSE.
//! - [`runner`]: finds the venv's Python and runs `compare/python/render_mitsuba.py`.
//! - [`crosscheck`]: export + both renders + test; [`report`]: its HTML page.
//! - [`bench`]: time to equal error, oracle vs Mitsuba.

pub mod bench;
pub mod crosscheck;
pub mod export;
pub mod ply;
pub mod report;
pub mod runner;
pub mod xml;
pub mod ztest;
