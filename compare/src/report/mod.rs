//! The study report: `index.html`, the SVG charts, and (through the study run) metrics.json,
//! metrics.csv and every image as EXR and PNG.
//!
//! | file | what |
//! |---|---|
//! | `index.html` | the page ([`html`]) |
//! | `metrics.json`, `metrics.csv` | every number (schema: compare/README.md) |
//! | `ground_truth.exr/.png` | the oracle's image, variance and AOVs |
//! | `methods/<id>.exr/.png` | each approximation, with `error.<metric>.Y` layers |
//! | `methods/<id>-error-<metric>.png` | false-colour error maps with their colour bar ([`colormap`]) |
//! | `charts/error-vs-cost.svg`, `charts/sweep-<method>-<parameter>.svg` | the charts ([`chart`]) |

pub mod chart;
pub mod colormap;
pub mod html;

use std::io;
use std::path::Path;

use scenes::layered::write_atomic;

use crate::study::result::StudyResult;

/// Writes the charts and `index.html` for `result` into `dir`.
pub fn write(result: &StudyResult, dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir.join("charts"))?;
    let cost = html::cost_chart(result);
    write_atomic(dir.join("charts/error-vs-cost.svg"), cost.as_bytes())?;
    let mut sweeps = Vec::new();
    for s in &result.sweeps {
        // The best variant's noise floor stands for the sweep's (one reference for all).
        let floor = result
            .variants
            .iter()
            .filter(|v| v.method == s.method)
            .filter_map(|v| {
                let m = v.metrics.iter().find(|m| m.mask == s.mask)?;
                m.values.iter().find(|e| e.metric == s.metric)
            })
            .map(|e| e.noise_floor)
            .next();
        let title = format!(
            "{}: {} over `{}` against {}",
            s.method, s.metric, s.mask, s.parameter
        );
        let svg = chart::error_vs_parameter(
            &s.parameter,
            &s.values,
            &s.errors,
            floor,
            s.breakpoint.as_deref(),
            &s.metric,
            &title,
        );
        write_atomic(
            dir.join(format!("charts/sweep-{}-{}.svg", s.method, s.parameter)),
            svg.as_bytes(),
        )?;
        let caption = match &s.breakpoint {
            Some(b) => format!(
                "{title}; break point at {} = {b} (error above {}× the sweep's best, {:.3e})",
                s.parameter, s.factor, s.best
            ),
            None => format!(
                "{title}; no break point within {}× the best ({:.3e})",
                s.factor, s.best
            ),
        };
        sweeps.push((caption, svg));
    }
    write_atomic(
        dir.join("index.html"),
        html::page(result, &cost, &sweeps).as_bytes(),
    )
}
