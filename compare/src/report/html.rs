//! `index.html`: one self-contained page (inline CSS, a few lines of JavaScript, SVG charts
//! inline and as files) drawn from the [`StudyResult`] alone, so every number on it is also in
//! metrics.json.
//!
//! Reading order: what was measured and on which adapter; the declared bounds, failing first;
//! error against cost with the Pareto front; error against every swept parameter; the metric
//! table (click a column to sort; rows that fail a bound or have NaN/Inf come first); then per
//! variant ground truth | approximation | error map, where hovering (or clicking) the
//! approximation flips it to the ground truth.

use std::fmt::Write as _;

use super::chart::{self, CostPoint};
use crate::markup::escape as esc;
use crate::study::result::{MaskMetrics, StudyResult, VariantResult};

fn num(v: f64) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() {
        if v > 0.0 { "∞" } else { "−∞" }.into()
    } else if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e4) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}

const STYLE: &str = r#"
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; color: #222; }
table { border-collapse: collapse; font-size: 13px; }
th, td { border: 1px solid #ccc; padding: 3px 7px; text-align: right; white-space: nowrap; }
td.reason { white-space: normal; text-align: left; }
th { background: #f3f3f3; cursor: pointer; }
td.l, th.l { text-align: left; }
tr.fail td { background: #fde2e2; }
.pass { color: #176b17; } .failtxt { color: #b00; font-weight: bold; }
.triple { display: flex; gap: 8px; align-items: flex-start; margin-bottom: 1.2em; }
.triple figure { margin: 0; } .triple img { image-rendering: pixelated; width: 256px; }
.triple img.err { width: auto; height: 256px; }
figcaption { font-size: 12px; color: #555; }
.note { background: #fff7d6; padding: 6px 10px; border-left: 4px solid #e0b000; }
"#;

const SCRIPT: &str = r#"
function sortTable(th) {
  const table = th.closest('table'), i = [...th.parentNode.children].indexOf(th);
  const rows = [...table.tBodies[0].rows], asc = th.dataset.asc !== '1';
  const key = r => { const t = r.cells[i].dataset.v ?? r.cells[i].textContent; const x = parseFloat(t); return isNaN(x) ? t : x; };
  rows.sort((a, b) => { const x = key(a), y = key(b); return (x > y ? 1 : x < y ? -1 : 0) * (asc ? 1 : -1); });
  th.dataset.asc = asc ? '1' : '0'; rows.forEach(r => table.tBodies[0].appendChild(r));
}
function flip(img, on) { img.src = on ? img.dataset.gt : img.dataset.approx; }
"#;

/// The whole page.
pub fn page(r: &StudyResult, cost_svgs: &[String], sweep_svgs: &[(String, String)]) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title><style>{STYLE}</style><script>{SCRIPT}</script></head><body>\n",
        esc(&r.title)
    );
    let _ = writeln!(h, "<h1>{}</h1><p>{}</p>", esc(&r.title), esc(&r.description));
    header(&mut h, r);
    thresholds(&mut h, r);
    let _ = writeln!(h, "<h2>Error against cost</h2>{}", cost_svgs.join("\n"));
    if !sweep_svgs.is_empty() {
        h += "<h2>Error against parameter</h2>\n";
        for (caption, svg) in sweep_svgs {
            let _ = writeln!(
                h,
                "<figure>{svg}<figcaption>{}</figcaption></figure>",
                esc(caption)
            );
        }
    }
    metric_table(&mut h, r);
    bias_table(&mut h, r);
    visibility_table(&mut h, r);
    second_ground_truth_table(&mut h, r);
    flicker(&mut h, r);
    images(&mut h, r);
    h += "<p>All numbers: <a href=\"metrics.json\">metrics.json</a>, <a href=\"metrics.csv\">metrics.csv</a>; all images as EXR beside the PNGs.</p></body></html>\n";
    h
}

fn header(h: &mut String, r: &StudyResult) {
    let gt = &r.ground_truth;
    let _ = writeln!(
        h,
        "<p>Study <code>{}</code> ({} mode), scene <code>{}</code>, {}×{} pixels.<br>Ground truth: oracle <code>{}</code>, {} spp, {:.2} s{}, mean relative standard error {:.2e} (its own noise; every metric below lists the floor it implies). Hash <code>{}</code>.</p>",
        esc(&r.study_file),
        r.mode,
        esc(&r.scene),
        r.width,
        r.height,
        gt.integrator,
        gt.spp,
        gt.seconds,
        if gt.cached { " (cached)" } else { "" },
        gt.mean_relative_std_error,
        &gt.hash[..16.min(gt.hash.len())]
    );
    let run = &r.run;
    let other = if run.mode == "quick" { "full" } else { "quick" };
    let _ = writeln!(
        h,
        "<p class=\"mode\"><b>{} mode</b>: {}×{} pixels, ground truth {} spp, {}×{} supersampling, {} warm-up + {} timed frames per variant; the {} bounds checked are those declared for {} mode or both ({} declared; run <code>verity report{}</code> for the {} ones). Run time {:.1} s{}.</p>",
        run.mode,
        run.resolution[0],
        run.resolution[1],
        run.ground_truth_spp,
        run.ssaa,
        run.ssaa,
        run.frames[0],
        run.frames[1],
        run.bounds_of_mode,
        run.mode,
        run.bounds_declared,
        if run.mode == "quick" { "" } else { " --quick" },
        other,
        run.wall_seconds,
        run.peak_memory_bytes
            .map(|b| format!(", peak memory {}", scenes::budget::human(b)))
            .unwrap_or_default()
    );
    if run.only_bounded {
        let _ = writeln!(
            h,
            "<p class=\"mode\"><b>Bounded variants only</b> (<code>--only-bounded</code>): {} of the {} variants the study declares, those a bound of {} mode applies to; no sweeps, and flicker only where a bound holds it. Run without the flag for the whole study.</p>",
            r.variants.len(),
            run.variants_declared,
            run.mode
        );
    }
    if let Some(s) = &r.scene_sweep {
        let values: Vec<String> = s
            .values
            .iter()
            .zip(&s.ground_truths)
            .map(|(v, g)| format!("{v} (<a href=\"{}\">ground truth</a>)", g.exr))
            .collect();
        let _ = writeln!(
            h,
            "<p>Scene sweep: <code>{}</code> sets {} to {}; every method is measured against each value's own ground truth (above: the first).</p>",
            esc(&s.parameter),
            s.fields
                .iter()
                .map(|f| format!("<code>{}</code>", esc(f)))
                .collect::<Vec<_>>()
                .join(", "),
            values.join(", ")
        );
    }
    let a = &r.adapter;
    let _ = writeln!(
        h,
        "<p>Costs measured on <b>{}</b> ({}, {}), from {}.</p>",
        esc(&a.name),
        esc(&a.backend),
        esc(&a.driver),
        a.timing_source.replace('_', " ")
    );
    if a.is_cpu {
        h.push_str("<p class=\"note\">This adapter is a CPU rasteriser: its times are CPU time, not GPU speed. Compare methods by the hardware-independent counters (texel fetches and loop iterations per pixel) as well.</p>\n");
    }
}

fn thresholds(h: &mut String, r: &StudyResult) {
    let failed = r.failures().len();
    let _ = writeln!(
        h,
        "<h2>Declared bounds: {} of {} hold</h2><table><thead><tr><th class=l>result</th><th class=l>variant</th><th class=l>metric</th><th class=l>mask</th><th>value</th><th>min</th><th>max</th><th class=l>reason</th></tr></thead><tbody>",
        r.thresholds.len() - failed,
        r.thresholds.len()
    );
    let mut rows: Vec<_> = r.thresholds.iter().collect();
    rows.sort_by_key(|t| t.passed);
    for t in rows {
        let _ = writeln!(
            h,
            "<tr class=\"{}\"><td class=l>{}</td><td class=l>{}</td><td class=l>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=reason>{}</td></tr>",
            if t.passed { "" } else { "fail" },
            if t.passed { "<span class=pass>holds</span>" } else { "<span class=failtxt>FAILS</span>" },
            esc(&t.variant),
            if t.on == "image" || t.on == "flicker" { t.metric.clone() } else { format!("{} of the {}", t.metric, t.on) },
            esc(&t.mask),
            num(t.value),
            t.min.map_or("".into(), num),
            t.max.map_or("".into(), num),
            esc(&t.reason)
        );
    }
    h.push_str("</tbody></table>\n");
}

/// Whether a variant fails a bound or has NaN/Inf.
fn failing(r: &StudyResult, v: &VariantResult) -> bool {
    v.non_finite_pixels > 0 || r.thresholds.iter().any(|t| !t.passed && t.variant == v.label)
}

/// "forward pass 12.3 ms; post-process pass 1.2 ms" (the ms/frame cell's tooltip).
fn pass_times(passes: &[realtime::timing::PassTime]) -> String {
    passes
        .iter()
        .map(|p| format!("{} {} ms", p.name, num(p.ms)))
        .collect::<Vec<_>>()
        .join("; ")
}

fn metric_table(h: &mut String, r: &StudyResult) {
    h.push_str("<h2>Metrics (mask <code>all</code>; other masks in metrics.json)</h2><table><thead><tr><th class=l onclick=\"sortTable(this)\">variant</th><th onclick=\"sortTable(this)\">ms/frame</th><th onclick=\"sortTable(this)\">texel fetches/px</th><th onclick=\"sortTable(this)\">loop iterations/px</th><th onclick=\"sortTable(this)\">samples/px</th><th onclick=\"sortTable(this)\">post-process taps/px</th><th onclick=\"sortTable(this)\">SSAO loads/px</th><th onclick=\"sortTable(this)\">NaN/Inf px</th>");
    for m in &r.metrics {
        let _ = write!(h, "<th onclick=\"sortTable(this)\">{m}</th>");
    }
    h.push_str("</tr></thead><tbody>\n");
    let mut rows: Vec<&VariantResult> = r.variants.iter().collect();
    rows.sort_by_key(|v| !failing(r, v));
    for v in rows {
        let opt = |x: Option<f64>| x.map_or("–".into(), num);
        let _ = write!(
            h,
            "<tr class=\"{}\"><td class=l>{}</td><td title=\"{}\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>",
            if failing(r, v) { "fail" } else { "" },
            esc(&v.label),
            esc(&pass_times(&v.cost.passes)),
            num(v.cost.frame_ms),
            opt(v.cost.texel_fetches_per_pixel),
            opt(v.cost.loop_iterations_per_pixel),
            v.cost.samples_per_pixel,
            opt(v.cost.post_taps_per_pixel),
            opt(v.cost.ssao_loads_per_pixel),
            v.non_finite_pixels
        );
        if let Some(all) = v.metrics.first() {
            for e in &all.values {
                let _ = write!(
                    h,
                    "<td data-v=\"{}\" title=\"noise floor {}\">{}</td>",
                    e.value,
                    num(e.noise_floor),
                    num(e.value)
                );
            }
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table><p>Hover a value for the reference's noise floor of that metric, a frame time for its passes.</p>\n");
}

/// Each variant's luminance bias over each mask: Σ test / Σ ground truth (what
/// `metric = "bias"` bounds) ± its standard error from the ground truth's noise estimate.
fn bias_table(h: &mut String, r: &StudyResult) {
    h.push_str("<h2>Bias per mask (luminance, Σ approximation / Σ ground truth)</h2><table><thead><tr><th class=l onclick=\"sortTable(this)\">variant</th>");
    for mask in &r.masks {
        let _ = write!(h, "<th onclick=\"sortTable(this)\">{}</th>", esc(&mask.name));
    }
    h.push_str("</tr></thead><tbody>\n");
    for v in &r.variants {
        let _ = write!(h, "<tr><td class=l>{}</td>", esc(&v.label));
        for mask in &r.masks {
            let bias = v.metrics.iter().find(|m| m.mask == mask.name).map(|m| &m.bias);
            match bias.filter(|b| b.ratio.Y.is_finite()) {
                Some(b) => {
                    let _ = write!(
                        h,
                        "<td data-v=\"{}\">{} ± {}</td>",
                        b.ratio.Y,
                        num(b.ratio.Y),
                        num(b.standard_error.Y)
                    );
                }
                None => h.push_str("<td>–</td>"),
            }
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table><p>1 is unbiased; ± one standard error of the ratio from the ground truth's noise (a dash: the ground truth sums to 0 there).</p>\n");
}

/// The visibility-factor metrics over `all`, when the study measures them.
fn visibility_table(h: &mut String, r: &StudyResult) {
    if r.variants.iter().all(|v| v.visibility.is_empty()) {
        return;
    }
    h.push_str("<h2>Visibility factor against the oracle's visible fraction</h2>");
    mask_tables(h, r, |v| &v.visibility);
}

/// The image's metrics against the `[second_ground_truth]` over every mask, when the study
/// has one, with its images.
fn second_ground_truth_table(h: &mut String, r: &StudyResult) {
    let Some(second) = &r.second_ground_truth else {
        return;
    };
    let _ = write!(
        h,
        "<h2>Against the second ground truth: {}</h2><p>The oracle's image of <code>{}</code> ({}), with the same settings, camera and masks as the ground truth.</p>",
        esc(&second.name),
        esc(&second.scene),
        if second.follows_scene_sweep {
            "one per scene-sweep value"
        } else {
            "one image for every scene-sweep value"
        }
    );
    h.push_str("<div class=triple>");
    for g in &second.images {
        let _ = write!(
            h,
            "<figure><img src=\"{}\" alt=\"second ground truth\"><figcaption><a href=\"{}\">{}</a></figcaption></figure>",
            esc(&g.png),
            esc(&g.exr),
            esc(&g.exr)
        );
    }
    h.push_str("</div>\n");
    mask_tables(h, r, |v| &v.second_ground_truth);
}

/// One table per mask of the metrics `of` each variant selects (visibility, second ground
/// truth), sortable.
fn mask_tables(h: &mut String, r: &StudyResult, of: impl Fn(&VariantResult) -> &[MaskMetrics]) {
    for mask in &r.masks {
        let _ = write!(
            h,
            "<h3>Mask <code>{}</code></h3><table><thead><tr><th class=l onclick=\"sortTable(this)\">variant</th>",
            esc(&mask.name)
        );
        for m in &r.metrics {
            let _ = write!(h, "<th onclick=\"sortTable(this)\">{m}</th>");
        }
        h.push_str("</tr></thead><tbody>\n");
        for v in &r.variants {
            let _ = write!(h, "<tr><td class=l>{}</td>", esc(&v.label));
            let values = of(v).iter().find(|m| m.mask == mask.name);
            for e in values.map_or(&[][..], |m| &m.values[..]) {
                let _ = write!(h, "<td data-v=\"{}\">{}</td>", e.value, num(e.value));
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</tbody></table>\n");
    }
}

fn flicker(h: &mut String, r: &StudyResult) {
    if r.flicker.is_empty() {
        return;
    }
    let _ = writeln!(
        h,
        "<h2>Temporal flicker</h2><p>Under {} ({} frames, one ground truth each); flicker is the mean change of the signed error between frames relative to the signal, beside what the ground truth's own noise gives.</p>",
        esc(&r.flicker[0].motion),
        r.flicker[0].frames
    );
    h.push_str("<table><thead><tr><th class=l>variant</th><th>frames</th><th>flicker</th><th>noise floor</th></tr></thead><tbody>\n");
    for f in &r.flicker {
        let _ = writeln!(
            h,
            "<tr><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&f.variant),
            f.frames,
            num(f.flicker),
            num(f.noise_floor)
        );
    }
    h.push_str("</tbody></table>\n");
}

fn images(h: &mut String, r: &StudyResult) {
    h.push_str("<h2>Images</h2><p>Ground truth | approximation (hover or click to flip to the ground truth) | error map of the chart metric; the other metrics' maps are linked below each.</p>\n");
    for v in &r.variants {
        let shown = v
            .error_pngs
            .iter()
            .find(|(m, _)| *m == r.chart.metric)
            .or(v.error_pngs.first());
        let (metric, file) = shown.map_or(("", ""), |(m, f)| (m.as_str(), f.as_str()));
        let others: Vec<String> = v
            .error_pngs
            .iter()
            .map(|(m, f)| format!("<a href=\"{f}\">{m}</a>"))
            .collect();
        let _ = writeln!(
            h,
            "<h3>{label}</h3><div class=triple><figure><img src=\"{gt_png}\" alt=\"ground truth\"><figcaption>ground truth (<a href=\"{gt}\">EXR</a>)</figcaption></figure><figure><img src=\"{png}\" data-gt=\"{gt_png}\" data-approx=\"{png}\" onmouseenter=\"flip(this,true)\" onmouseleave=\"flip(this,false)\" onclick=\"flip(this,this.src.endsWith('{png}'))\" alt=\"approximation\"><figcaption>{label} (<a href=\"{exr}\">EXR</a>)</figcaption></figure><figure><img class=err src=\"{file}\" alt=\"{metric} error map\"><figcaption>{metric} error (magma, 0 to the 99th percentile); maps: {links}</figcaption></figure></div>",
            label = esc(&v.label),
            gt = v.ground_truth_exr,
            gt_png = v.ground_truth_png,
            png = v.png,
            exr = v.exr,
            links = others.join(", ")
        );
    }
}

/// What a cost chart puts on its x axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostAxis {
    /// Median frame time (`charts/error-vs-cost.svg`).
    FrameTime,
    /// Texel fetches per pixel from the counting frame (`charts/error-vs-fetches.svg`); drawn
    /// only when every variant was counted.
    TexelFetches,
}

/// The error-vs-cost chart of the study's chart metric over its chart mask, against `axis`;
/// None when a variant lacks that cost.
pub fn cost_chart(r: &StudyResult, axis: CostAxis) -> Option<String> {
    let (metric, mask) = (r.chart.metric.as_str(), r.chart.mask.as_str());
    // One scene: the first scene-sweep point (every point has the same costs' methods).
    let first_scene = r.variants.first().map(|v| v.scene.clone()).unwrap_or_default();
    let points: Vec<CostPoint> = r
        .variants
        .iter()
        .filter(|v| v.scene == first_scene)
        .map(|v| {
            Some(CostPoint {
                label: v.label.clone(),
                cost: match axis {
                    CostAxis::FrameTime => v.cost.frame_ms,
                    CostAxis::TexelFetches => v.cost.texel_fetches_per_pixel?,
                },
                error: r.value(&v.label, mask, metric).unwrap_or(f64::NAN),
            })
        })
        .collect::<Option<_>>()?;
    Some(match axis {
        CostAxis::FrameTime => {
            let title = format!("{metric} over `{mask}` against frame time on {}", r.adapter.name);
            let cost = format!("ms/frame ({})", r.adapter.timing_source.replace('_', " "));
            chart::error_vs_cost(&points, metric, &cost, "ms", &title)
        }
        CostAxis::TexelFetches => {
            let title =
                format!("{metric} over `{mask}` against texel fetches per pixel (hardware-independent)");
            chart::error_vs_cost(&points, metric, "texel fetches per pixel", "fetches/px", &title)
        }
    })
}
