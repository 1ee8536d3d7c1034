//! SVG charts: error against cost with the Pareto front, and error against a swept parameter
//! with its break point. Plain SVG 1.1 text, readable in any browser and embeddable in HTML;
//! axes are logarithmic where values span decades.

use std::fmt::Write as _;

use crate::markup::escape as esc;

/// One point of an error-vs-cost chart.
#[derive(Clone, Debug)]
pub struct CostPoint {
    /// Variant label.
    pub label: String,
    /// Cost, ms.
    pub cost: f64,
    /// Error (lower is better).
    pub error: f64,
}

/// Indices of the Pareto-optimal points: no other point has both lower-or-equal cost and
/// lower-or-equal error with one of them strictly lower. Non-finite points are never optimal.
pub fn pareto_front(points: &[CostPoint]) -> Vec<usize> {
    let ok = |p: &CostPoint| p.cost.is_finite() && p.error.is_finite();
    (0..points.len())
        .filter(|&i| {
            let p = &points[i];
            ok(p)
                && !points.iter().any(|q| {
                    ok(q) && q.cost <= p.cost && q.error <= p.error && (q.cost < p.cost || q.error < p.error)
                })
        })
        .collect()
}

const W: f64 = 640.0;
const H: f64 = 400.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 20.0;
const TOP: f64 = 30.0;
const BOTTOM: f64 = 60.0;
/// Height of one legend row below the chart.
const LEGEND_ROW: f64 = 14.0;

/// A log or linear axis mapping values to pixels.
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    from: f64,
    to: f64,
    /// Tick values to use instead of the automatic ones (a sweep's parameter values).
    fixed_ticks: Option<Vec<f64>>,
}

impl Axis {
    /// An axis over `values` (finite, > 0 for log), padded a little.
    fn fit(values: impl Iterator<Item = f64>, from: f64, to: f64) -> Axis {
        let v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
        let (mut lo, mut hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
        if !lo.is_finite() {
            (lo, hi) = (1.0, 10.0);
        }
        let log = lo > 0.0 && hi / lo >= 8.0;
        if log {
            (lo, hi) = (lo / 1.5, hi * 1.5);
        } else {
            let pad = ((hi - lo) * 0.1).max(hi.abs() * 0.05).max(1e-12);
            (lo, hi) = (lo - pad, hi + pad);
        }
        Axis {
            lo,
            hi,
            log,
            from,
            to,
            fixed_ticks: None,
        }
    }

    fn px(&self, v: f64) -> f64 {
        let t = if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        };
        self.from + t * (self.to - self.from)
    }

    /// Tick values: the fixed ones if given; else decades on a log axis (with 2 and 5 between
    /// when it spans less than two), and 1-2-5 steps on a linear one.
    fn ticks(&self) -> Vec<f64> {
        if let Some(t) = &self.fixed_ticks {
            return t.clone();
        }
        if self.log {
            let (a, b) = (self.lo.log10().floor() as i32, self.hi.log10().ceil() as i32);
            let mantissas: &[f64] = if b - a <= 2 { &[1.0, 2.0, 5.0] } else { &[1.0] };
            return (a..=b)
                .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
                .filter(|t| (self.lo..=self.hi).contains(t))
                .collect();
        }
        let raw = (self.hi - self.lo) / 5.0;
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|s| *s >= raw)
            .unwrap_or(mag * 10.0);
        let first = (self.lo / step).ceil() as i64;
        let last = (self.hi / step).floor() as i64;
        (first..=last).map(|k| k as f64 * step).collect()
    }
}

/// Frame, ticks and axis titles.
/// The frame, ticks and titles; `legend_rows` rows of legend room are added below the chart.
fn axes(svg: &mut String, x: &Axis, y: &Axis, x_title: &str, y_title: &str, title: &str, legend_rows: usize) {
    let height = H + LEGEND_ROW * legend_rows as f64 + if legend_rows > 0 { 8.0 } else { 0.0 };
    let _ = write!(
        svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {height}" width="{W}" height="{height}" font-family="sans-serif" font-size="11">
<rect x="0" y="0" width="{W}" height="{height}" fill="white"/>
<text x="{}" y="18" text-anchor="middle" font-size="13">{}</text>
<rect x="{LEFT}" y="{TOP}" width="{}" height="{}" fill="none" stroke="#444"/>
"##,
        W / 2.0,
        esc(title),
        W - LEFT - RIGHT,
        H - TOP - BOTTOM
    );
    for t in x.ticks() {
        let p = x.px(t);
        let _ = writeln!(
            svg,
            r##"<line x1="{p:.1}" y1="{:.1}" x2="{p:.1}" y2="{TOP}" stroke="#ddd"/><text x="{p:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            H - BOTTOM,
            H - BOTTOM + 15.0,
            fmt_tick(t)
        );
    }
    for t in y.ticks() {
        let p = y.px(t);
        let _ = writeln!(
            svg,
            r##"<line x1="{LEFT}" y1="{p:.1}" x2="{:.1}" y2="{p:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            W - RIGHT,
            LEFT - 5.0,
            p + 4.0,
            fmt_tick(t)
        );
    }
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text><text transform="translate(16 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        LEFT + (W - LEFT - RIGHT) / 2.0,
        H - 20.0,
        esc(x_title),
        TOP + (H - TOP - BOTTOM) / 2.0,
        esc(y_title)
    );
}

fn fmt_tick(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e4) {
        format!("{v:.0e}")
    } else {
        format!("{}", (v * 1000.0).round() / 1000.0)
    }
}

/// Error against cost, Pareto-optimal points filled and joined.
pub fn error_vs_cost(
    points: &[CostPoint],
    metric: &str,
    cost_title: &str,
    unit: &str,
    title: &str,
) -> String {
    let x = Axis::fit(points.iter().map(|p| p.cost), LEFT, W - RIGHT);
    let y = Axis::fit(points.iter().map(|p| p.error), H - BOTTOM, TOP);
    let mut svg = String::new();
    axes(&mut svg, &x, &y, cost_title, metric, title, 0);
    let mut front = pareto_front(points);
    front.sort_by(|&a, &b| points[a].cost.total_cmp(&points[b].cost));
    let path: Vec<String> = front
        .iter()
        .map(|&i| format!("{:.1},{:.1}", x.px(points[i].cost), y.px(points[i].error)))
        .collect();
    let _ = writeln!(
        svg,
        r##"<polyline points="{}" fill="none" stroke="#d33" stroke-width="1.5"/>"##,
        path.join(" ")
    );
    for (i, p) in points.iter().enumerate() {
        if !(p.cost.is_finite() && p.error.is_finite()) {
            continue;
        }
        let on = front.contains(&i);
        // Labels of points in the right half go to their left, so they stay inside the chart.
        let right_half = x.px(p.cost) > (LEFT + W - RIGHT) / 2.0;
        let _ = writeln!(
            svg,
            r##"<g><title>{} — {:.4} {unit}, {metric} {:.3e}{}</title><circle cx="{:.1}" cy="{:.1}" r="4.5" fill="{}" stroke="#d33"/><text x="{:.1}" y="{:.1}" font-size="9" text-anchor="{}">{}</text></g>"##,
            esc(&p.label),
            p.cost,
            p.error,
            if on { " (Pareto-optimal)" } else { "" },
            x.px(p.cost),
            y.px(p.error),
            if on { "#d33" } else { "white" },
            x.px(p.cost) + if right_half { -6.0 } else { 6.0 },
            y.px(p.error) - 6.0,
            if right_half { "end" } else { "start" },
            esc(&p.label)
        );
    }
    svg += "</svg>\n";
    svg
}

/// One line of an error-against-parameter chart.
pub struct Series<'a> {
    /// Legend text (empty for a single unnamed line).
    pub label: &'a str,
    /// The error at each value.
    pub errors: &'a [f64],
    /// The value it breaks at, if any.
    pub breakpoint: Option<&'a str>,
}

/// Line colours of the series, in order (then repeated, dashed).
const SERIES_COLOURS: [&str; 8] = ["#36c", "#d62", "#393", "#93c", "#c39", "#088", "#b80", "#555"];

/// One error-against-parameter chart's axes and x values, shared by its series.
struct Plot<'a> {
    parameter: &'a str,
    metric: &'a str,
    values: &'a [String],
    xs: &'a [f64],
    x: &'a Axis,
    y: &'a Axis,
}

impl Plot<'_> {
    /// Series `n` of `count`: its line, its points (with tooltips), its break point and, when
    /// there are several, its legend row.
    fn series(&self, svg: &mut String, s: &Series, n: usize, count: usize) {
        let colour = if count == 1 {
            SERIES_COLOURS[0]
        } else {
            SERIES_COLOURS[n % SERIES_COLOURS.len()]
        };
        // Past the palette, lines repeat its colours dashed (and dotted after that), so no
        // two series look alike up to three times its length.
        let dash = ["", r#" stroke-dasharray="6 3""#, r#" stroke-dasharray="1.5 2""#]
            [(n / SERIES_COLOURS.len()).min(2)];
        let mut order: Vec<usize> = (0..self.values.len())
            .filter(|&i| s.errors[i].is_finite())
            .collect();
        order.sort_by(|&a, &b| self.xs[a].total_cmp(&self.xs[b]));
        let line: Vec<String> = order
            .iter()
            .map(|&i| format!("{:.1},{:.1}", self.x.px(self.xs[i]), self.y.px(s.errors[i])))
            .collect();
        let _ = writeln!(
            svg,
            r##"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.5"{dash}/>"##,
            line.join(" ")
        );
        let name = if s.label.is_empty() {
            String::new()
        } else {
            format!("{}: ", esc(s.label))
        };
        for &i in &order {
            let broken = s.breakpoint == Some(self.values[i].as_str());
            let _ = writeln!(
                svg,
                r##"<g><title>{name}{} = {}: {} {:.3e}{}</title><circle cx="{:.1}" cy="{:.1}" r="4.5" fill="{}" stroke="{colour}"/></g>"##,
                self.parameter,
                esc(&self.values[i]),
                self.metric,
                s.errors[i],
                if broken { " (break point)" } else { "" },
                self.x.px(self.xs[i]),
                self.y.px(s.errors[i]),
                if broken { "#d33" } else { colour }
            );
        }
        if let Some(b) = s.breakpoint.and_then(|b| self.values.iter().position(|v| v == b)) {
            let p = self.x.px(self.xs[b]);
            let _ = writeln!(
                svg,
                r##"<line x1="{p:.1}" y1="{TOP}" x2="{p:.1}" y2="{:.1}" stroke="{colour}" stroke-dasharray="2 2"/>"##,
                H - BOTTOM
            );
        }
        if count > 1 {
            // Legend below the chart, one row per series, with its break point.
            let (lx, ly) = (LEFT, H + 4.0 + LEGEND_ROW * n as f64);
            let _ = writeln!(
                svg,
                r##"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{colour}" stroke-width="2"{dash}/><text x="{:.1}" y="{ly:.1}" font-size="9">{}{}</text>"##,
                ly - 3.0,
                lx + 14.0,
                ly - 3.0,
                lx + 18.0,
                esc(s.label),
                s.breakpoint
                    .map_or(String::new(), |b| format!(" (breaks at {})", esc(b)))
            );
        }
    }
}

/// Error against a swept parameter (values in listed order along x), one line per series,
/// with the noise floor and each series' break point marked.
pub fn error_vs_parameter(
    parameter: &str,
    values: &[String],
    series: &[Series],
    noise_floor: Option<f64>,
    metric: &str,
    title: &str,
) -> String {
    let numeric: Option<Vec<f64>> = values.iter().map(|v| v.parse::<f64>().ok()).collect();
    let xs: Vec<f64> = match &numeric {
        Some(v) => v.clone(),
        None => (0..values.len()).map(|i| i as f64).collect(),
    };
    let mut x = Axis::fit(xs.iter().copied(), LEFT, W - RIGHT);
    if numeric.is_some() {
        x.fixed_ticks = Some(xs.clone());
    }
    let y = Axis::fit(
        series
            .iter()
            .flat_map(|s| s.errors.iter().copied())
            .chain(noise_floor.filter(|f| *f > 0.0)),
        H - BOTTOM,
        TOP,
    );
    let mut svg = String::new();
    let legend_rows = if series.len() > 1 { series.len() } else { 0 };
    axes(&mut svg, &x, &y, parameter, metric, title, legend_rows);
    if let Some(f) = noise_floor.filter(|f| f.is_finite() && *f > 0.0) {
        let p = y.px(f);
        let _ = writeln!(
            svg,
            r##"<line x1="{LEFT}" y1="{p:.1}" x2="{:.1}" y2="{p:.1}" stroke="#888" stroke-dasharray="4 3"/><text x="{:.1}" y="{:.1}" text-anchor="end" fill="#666">reference noise floor</text>"##,
            W - RIGHT,
            W - RIGHT - 4.0,
            p - 4.0
        );
    }
    if numeric.is_none() {
        for (i, v) in values.iter().enumerate() {
            let _ = writeln!(
                svg,
                r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
                x.px(xs[i]),
                H - BOTTOM + 28.0,
                esc(v)
            );
        }
    }
    let plot = Plot {
        parameter,
        metric,
        values,
        xs: &xs,
        x: &x,
        y: &y,
    };
    for (n, s) in series.iter().enumerate() {
        plot.series(&mut svg, s, n, series.len());
    }
    if series.len() == 1 {
        if let Some(b) = series[0]
            .breakpoint
            .and_then(|b| values.iter().position(|v| v == b))
        {
            let _ = writeln!(
                svg,
                r##"<text x="{:.1}" y="{:.1}" fill="#d33">break point</text>"##,
                x.px(xs[b]) + 4.0,
                TOP + 12.0
            );
        }
    }
    svg += "</svg>\n";
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(cost: f64, error: f64) -> CostPoint {
        CostPoint {
            label: format!("{cost}/{error}"),
            cost,
            error,
        }
    }

    #[test]
    fn pareto_front_keeps_exactly_the_undominated_points() {
        let pts = [
            p(1.0, 10.0),
            p(2.0, 5.0),
            p(3.0, 6.0),
            p(4.0, 1.0),
            p(2.0, 5.0),
            p(0.5, f64::NAN),
        ];
        // (3, 6) is dominated by (2, 5); the duplicate (2, 5) points do not dominate each other.
        assert_eq!(pareto_front(&pts), vec![0, 1, 3, 4]);
        let svg = error_vs_cost(&pts, "relmse", "ms", "ms", "t");
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert_eq!(svg.matches("(Pareto-optimal)").count(), 4);
    }

    #[test]
    fn parameter_chart_marks_the_break_point() {
        let values: Vec<String> = ["16", "8", "4", "2", "1"].map(String::from).to_vec();
        let one = Series {
            label: "",
            errors: &[1e-6, 2e-6, 1e-5, 1e-4, 1e-3],
            breakpoint: Some("2"),
        };
        let svg = error_vs_parameter("n", &values, &[one], Some(1e-6), "relmse", "t");
        assert!(svg.contains("n = 2: relmse 1.000e-4 (break point)"));
        assert!(svg.contains("reference noise floor") && svg.contains(">break point<"));
        // Several series: one line each, a legend naming each and where it breaks.
        let two = [
            Series {
                label: "pcss",
                errors: &[1e-4, 1e-4, 2e-4, 3e-4, 4e-4],
                breakpoint: None,
            },
            Series {
                label: "shadow_hard",
                errors: &[1e-3, 5e-3, 1e-2, 5e-2, 1e-1],
                breakpoint: Some("8"),
            },
        ];
        let svg = error_vs_parameter("light_size", &values, &two, None, "relmse", "t");
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert!(svg.contains("shadow_hard (breaks at 8)") && svg.contains("pcss: light_size = 16"));
        // Past the palette's eight colours the lines are dashed: eleven series, three dashed.
        let labels: Vec<String> = (0..11).map(|k| format!("m{k}")).collect();
        let errors = [1e-4, 1e-4, 2e-4, 3e-4, 4e-4];
        let many: Vec<Series> = labels
            .iter()
            .map(|l| Series {
                label: l,
                errors: &errors,
                breakpoint: None,
            })
            .collect();
        let svg = error_vs_parameter("light_size", &values, &many, None, "relmse", "t");
        assert_eq!(svg.matches("<polyline").count(), 11);
        // Each dashed series dashes its line and its legend swatch.
        assert_eq!(svg.matches(r#"stroke-dasharray="6 3""#).count(), 2 * 3);
    }
}
