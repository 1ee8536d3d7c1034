//! The study report: `index.html`, the SVG charts, and (through the study run) metrics.json,
//! metrics.csv and every image as EXR and PNG.
//!
//! | file | what |
//! |---|---|
//! | `index.html` | the page ([`html`]) |
//! | `metrics.json`, `metrics.csv` | every number (schema: compare/README.md) |
//! | `ground_truth.exr/.png` | the oracle's image, variance and AOVs (`ground_truth--<parameter>-<value>.*` at each scene-sweep value) |
//! | `methods/<id>.exr/.png` | each approximation, with `error.<metric>.Y` layers |
//! | `methods/<id>-error-<metric>.png` | false-colour error maps with their colour bar ([`crate::colormap`]) |
//! | `charts/error-vs-cost.svg`, `charts/error-vs-fetches.svg` (when counted), `charts/sweep-<method>-<parameter>.svg`, `charts/scene-<parameter>-<image\|visibility\|second_ground_truth>.svg` | the charts ([`chart`]) |

pub mod chart;
pub mod html;

use std::io;
use std::path::Path;

use scenes::layered::write_atomic;

use crate::study::result::StudyResult;

/// Writes the charts and `index.html` for `result` into `dir`.
pub fn write(result: &StudyResult, dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir.join("charts"))?;
    let mut costs = Vec::new();
    for (axis, file) in [
        (html::CostAxis::FrameTime, "charts/error-vs-cost.svg"),
        (html::CostAxis::TexelFetches, "charts/error-vs-fetches.svg"),
    ] {
        if let Some(svg) = html::cost_chart(result, axis) {
            write_atomic(dir.join(file), svg.as_bytes())?;
            costs.push(svg);
        }
    }
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
        let line = chart::Series {
            label: "",
            errors: &s.errors,
            breakpoint: s.breakpoint.as_deref(),
        };
        let svg = chart::error_vs_parameter(&s.parameter, &s.values, &[line], floor, &s.metric, &title);
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
    if let Some(s) = &result.scene_sweep {
        sweeps.extend(scene_sweep_charts(s, dir)?);
    }
    write_atomic(
        dir.join("index.html"),
        html::page(result, &costs, &sweeps).as_bytes(),
    )
}

/// The scene sweep's charts, one per measured target (image, visibility with
/// `visibility_of`, the image against a `[second_ground_truth]`): every method grid point as a line against the scene parameter.
fn scene_sweep_charts(
    s: &crate::study::result::SceneSweepResult,
    dir: &Path,
) -> io::Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for on in ["image", "visibility", "second_ground_truth"] {
        let lines: Vec<chart::Series> = s
            .series
            .iter()
            .filter_map(|x| {
                let e = match on {
                    "image" => Some(&x.image),
                    "visibility" => x.visibility.as_ref(),
                    _ => x.second_ground_truth.as_ref(),
                }?;
                Some(chart::Series {
                    label: &x.variant,
                    errors: &e.errors,
                    breakpoint: e.breakpoint.as_deref(),
                })
            })
            .collect();
        if lines.is_empty() {
            continue;
        }
        let what = match on {
            "image" => "the image",
            "visibility" => "the visibility factor",
            _ => "the image against the second ground truth",
        };
        let title = format!(
            "{} of {what} over `{}` against the scene's {}",
            s.metric, s.mask, s.parameter
        );
        let svg = chart::error_vs_parameter(&s.parameter, &s.values, &lines, None, &s.metric, &title);
        write_atomic(
            dir.join(format!("charts/scene-{}-{on}.svg", s.parameter)),
            svg.as_bytes(),
        )?;
        let breaks: Vec<String> = lines
            .iter()
            .filter_map(|l| Some(format!("{} at {}", l.label, l.breakpoint?)))
            .collect();
        let caption = format!(
            "{title} ({} = {}); one ground truth per value. Break points (error above {}× the line's best): {}",
            s.parameter,
            s.fields.join(", "),
            s.factor,
            if breaks.is_empty() {
                "none".to_string()
            } else {
                breaks.join("; ")
            }
        );
        out.push((caption, svg));
    }
    Ok(out)
}
