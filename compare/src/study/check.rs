//! Whole-study checks once every field is read: unique masks and labels, and thresholds that
//! name declared methods, masks and metrics and select at least one variant.

use scenes::toml::read::Table;
use scenes::SceneError;

use super::model::*;

/// Mask names are unique: thresholds and the report select masks by name.
pub(super) fn check_unique_masks(masks: &[MaskSpec], doc: &Table) -> Result<(), SceneError> {
    for (i, m) in masks.iter().enumerate() {
        if let Some(first) = masks[..i].iter().position(|k| k.name() == m.name()) {
            let tables = doc.req("mask")?.tables()?;
            let line = tables[first]
                .line
                .map_or(String::new(), |l| format!(" (line {l})"));
            return Err(tables[i]
                .req("name")?
                .err(format!(
                    "a mask named `{}` is already declared, mask[{first}]{line}",
                    m.name()
                ))
                .hint("give each [[mask]] its own name"));
        }
    }
    Ok(())
}

/// Two entries must not measure under one name (their reports would overwrite each other).
/// Builds the variants: call after [`super::plan::check_count`].
pub(super) fn check_unique_labels(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let mut seen = std::collections::HashSet::new();
    for v in study.methods.iter().flat_map(MethodSpec::variants) {
        if !seen.insert(v.method_label()) {
            return Err(doc
                .err(format!(
                    "two [[method]] entries measure the variant `{}`",
                    v.method_label()
                ))
                .field("method")
                .hint("give one of them a label = \"…\""));
        }
    }
    Ok(())
}

/// Thresholds name declared methods, masks and metrics and select at least one variant; the
/// stability metric is measured, its mask declared. Builds the variants: call after
/// [`super::plan::check_count`].
pub(super) fn check_references(study: &Study, doc: &Table) -> Result<(), SceneError> {
    let thresholds = doc
        .get("threshold")
        .map(|f| f.tables())
        .transpose()?
        .unwrap_or_default();
    let points = study.scene_points();
    let everywhere = study.variants();
    let first = study.variants_at(&points[0]);
    for (th, t) in study.thresholds.iter().zip(&thresholds) {
        let Some(m) = study
            .methods
            .iter()
            .find(|m| m.label.as_ref().unwrap_or(&m.name) == &th.method)
        else {
            let names: Vec<&str> = study
                .methods
                .iter()
                .map(|m| m.label.as_ref().unwrap_or(&m.name).as_str())
                .collect();
            return Err(t.req("method")?.err(format!(
                "no [[method]] named `{}` in this study; methods: {}",
                th.method,
                names.join(", ")
            )));
        };
        let of_this_entry = everywhere
            .iter()
            .filter(|v| v.method == m.name && v.label == m.label);
        if !of_this_entry.clone().any(|v| th.applies_to(v)) {
            if !th.scene.is_empty() {
                let declared = study.scene_sweep.as_ref().map_or("none".to_string(), |s| {
                    let values: Vec<&str> = s.values.iter().map(|(v, _)| v.as_str()).collect();
                    format!("`{}` = {}", s.name, values.join(", "))
                });
                return Err(t.req("scene")?.err(format!(
                    "no scene-sweep point has these values; the study's scene sweep: {declared}"
                )));
            }
            return Err(t.req("params")?.err(format!(
                "no variant of `{}` has these parameter values",
                th.method
            )));
        }
        if th.on == Target::Flicker {
            if study.stability.flicker.is_none() {
                return Err(t
                    .req("on")?
                    .err("measuring `flicker` needs a [stability.flicker] motion"));
            }
            if !first.iter().any(|v| th.applies_to(v)) {
                return Err(t
                    .req("on")?
                    .err("flicker is measured at the first scene-sweep value only; this bound selects none of its variants"));
            }
        }
        if th.on == Target::Visibility && study.visibility_of.is_none() {
            return Err(t
                .req("on")?
                .err("measuring `visibility` needs `visibility_of = \"<light>\"` in [ground_truth]"));
        }
        if th.on == Target::SecondGroundTruth && study.second_ground_truth.is_none() {
            return Err(t
                .req("on")?
                .err("measuring against `second_ground_truth` needs a [second_ground_truth] table"));
        }
        if th.mask != "all" && !study.masks.iter().any(|k| k.name() == th.mask) {
            return Err(t.req("mask")?.err(format!("no [[mask]] named `{}`", th.mask)));
        }
        // The bias is measured whatever the study's `metrics` (model.rs `Measure::Bias`).
        match th.metric {
            Measure::Metric(metric) if !study.metrics.contains(&metric) => {
                return Err(t
                    .req("metric")?
                    .err(format!("`{metric}` is not in the study's `metrics`")));
            }
            _ => {}
        }
    }
    // `[stability]`'s own fields where written; the defaults (relmse over `all`) are
    // reported at the study's `metrics`, which leaves them out.
    let stability = doc.get("stability").map(|f| f.table()).transpose()?;
    let located = |key: &str, message: String| -> SceneError {
        match stability.as_ref().and_then(|t| t.get(key)) {
            Some(f) => f.err(message),
            None => doc
                .get("metrics")
                .map_or_else(|| doc.err(message.clone()), |f| f.err(message.clone()))
                .field(format!("stability.{key}"))
                .hint(format!("set [stability] {key} = …, the default is not measured")),
        }
    };
    let m = &study.stability.mask;
    if m != "all" && !study.masks.iter().any(|k| k.name() == m) {
        return Err(located("mask", format!("no [[mask]] named `{m}`")));
    }
    if study.stability.metric.higher_is_better() {
        return Err(located(
            "metric",
            format!(
                "`{}`: break points need an error metric (lower is better), not psnr or ssim",
                study.stability.metric
            ),
        ));
    }
    if !study.metrics.contains(&study.stability.metric) {
        return Err(located(
            "metric",
            format!("`{}` is not in the study's `metrics`", study.stability.metric),
        ));
    }
    Ok(())
}
