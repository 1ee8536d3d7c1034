//! Stability analysis: error against each swept parameter with its break point, error
//! against a scene parameter, and temporal flicker under a slow camera or light motion.
//!
//! - **Break point**: walking a sweep in the order listed (from the method's good regime into
//!   its failure regime), the first value whose error exceeds `factor` × the sweep's best
//!   error, or whose image has NaN/Inf pixels. The same rule runs along a scene sweep for
//!   each method grid point (a light growing, a blocker rising).
//! - **Flicker**: F frames of a slow motion — the camera orbiting the point `orbit_distance`
//!   ahead of it by `orbit_degrees` per frame about world +Y, or scene fields (a light's
//!   position) shifted by `step` per frame, each frame with its own ground truth. With
//!   e_k = a_k − r_k the signed error of frame k,
//!   flicker = mean over k, pixels and channels of |e_{k+1} − e_k| / (|r_k| + 0.01): how much the
//!   error pattern changes between frames, relative to the signal. Only pixels interior in both
//!   frames count ([`Mask::interior`]): a moving silhouette changes every method's error, and
//!   that is the rasteriser's aliasing, not the method's flicker. Its noise floor is what the
//!   reference's own noise alone gives: E|n_{k+1} − n_k| = √(2/π)·√(σ²_k + σ²_{k+1}) for
//!   independent normal errors (the mean absolute value of a normal deviate). The sums run in
//!   f64; a NaN or ±Inf pixel of an approximation makes its flicker NaN (which holds no bound)
//!   instead of being skipped, and a motion that leaves no pixel interior in two consecutive
//!   frames is an error, not a flicker of 0.

use glam::{DVec3, Vec3};
use scenes::{RenderSettings, Scene};

use super::rasters::{RasterKey, Rasters};
use super::result::{
    FlickerResult, GroundTruthInfo, SceneSeries, SceneSweepResult, SeriesErrors, StudyResult, SweepResult,
};
use super::setup::{flicker_raster_settings, ground_truth, prepare, RunOptions, StudyError};
use super::{shifted, Flicker, Motion, ScenePoint, Study, Variant};
use crate::metrics::{Mask, RgbImage, RELATIVE_EPSILON};

/// One [`SweepResult`] per method and swept parameter, the other swept parameters at their
/// first listed value.
pub fn sweeps(study: &Study, variants: &[Variant], result: &StudyResult) -> Vec<SweepResult> {
    let metric = study.stability.metric.name();
    let mask = study.stability.mask.as_str();
    let mut out = Vec::new();
    for spec in &study.methods {
        for (key, values) in &spec.sweep {
            let firsts: Vec<(&String, &String)> = spec
                .sweep
                .iter()
                .filter(|(k, _)| k != key)
                .map(|(k, v)| (k, &v[0]))
                .collect();
            let points: Vec<&Variant> = values
                .iter()
                .filter_map(|val| {
                    variants.iter().find(|v| {
                        v.method == spec.name
                            && v.swept.iter().any(|(k, x)| k == key && x == val)
                            && firsts
                                .iter()
                                .all(|(k, x)| v.swept.iter().any(|(k2, x2)| k2 == *k && x2 == *x))
                    })
                })
                .collect();
            let rows: Vec<_> = points
                .iter()
                .map(|v| {
                    result
                        .variants
                        .iter()
                        .find(|r| r.label == v.label())
                        .expect("measured")
                })
                .collect();
            let errors: Vec<f64> = rows
                .iter()
                .map(|r| result.value(&r.label, mask, metric).unwrap_or(f64::NAN))
                .collect();
            let non_finite: Vec<usize> = rows.iter().map(|r| r.non_finite_pixels).collect();
            let factor = study.stability.breakpoint_factor;
            let (best, breakpoint) = breakpoint(&errors, &non_finite, factor);
            out.push(SweepResult {
                method: spec.name.clone(),
                parameter: key.clone(),
                metric: metric.into(),
                mask: mask.into(),
                values: values.clone(),
                frame_ms: rows.iter().map(|r| r.cost.frame_ms).collect(),
                errors,
                non_finite,
                best,
                breakpoint: breakpoint.map(|i| values[i].clone()),
                factor,
            });
        }
    }
    out
}

/// Every method grid point (`at_first`, the variants of the first scene point) along the
/// study's scene sweep, on the image and (with `visibility_of`) on the visibility factor.
pub fn scene_sweep(
    study: &Study,
    at_first: &[Variant],
    ground_truths: Vec<GroundTruthInfo>,
    result: &StudyResult,
) -> Option<SceneSweepResult> {
    let sweep = study.scene_sweep.as_ref()?;
    let metric = study.stability.metric.name();
    let mask = study.stability.mask.as_str();
    let factor = study.stability.breakpoint_factor;
    let values: Vec<String> = sweep.values.iter().map(|(v, _)| v.clone()).collect();
    let series = at_first
        .iter()
        .map(|v| {
            let along = |on: &str| {
                let mut errors = Vec::new();
                let mut non_finite = Vec::new();
                for value in &values {
                    let label = Variant {
                        scene: vec![(sweep.name.clone(), value.clone())],
                        ..v.clone()
                    }
                    .label();
                    errors.push(result.value_on(&label, on, mask, metric).unwrap_or(f64::NAN));
                    non_finite.push(
                        result
                            .variants
                            .iter()
                            .find(|r| r.label == label)
                            .map_or(0, |r| r.non_finite_pixels),
                    );
                }
                let (best, at) = breakpoint(&errors, &non_finite, factor);
                SeriesErrors {
                    errors,
                    non_finite,
                    best,
                    breakpoint: at.map(|i| values[i].clone()),
                }
            };
            SceneSeries {
                variant: v.method_label(),
                method: v.method.clone(),
                image: along("image"),
                visibility: study.visibility_of.as_ref().map(|_| along("visibility")),
                second_ground_truth: study
                    .second_ground_truth
                    .as_ref()
                    .map(|_| along("second_ground_truth")),
            }
        })
        .collect();
    Some(SceneSweepResult {
        parameter: sweep.name.clone(),
        fields: sweep.set.clone(),
        values,
        ground_truths,
        metric: metric.into(),
        mask: mask.into(),
        factor,
        series,
    })
}

/// The best finite error and the index of the first value past `factor` × best (or non-finite).
pub fn breakpoint(errors: &[f64], non_finite: &[usize], factor: f64) -> (f64, Option<usize>) {
    let best = errors
        .iter()
        .copied()
        .filter(|e| e.is_finite())
        .fold(f64::INFINITY, f64::min);
    let at =
        (0..errors.len()).find(|&i| non_finite[i] > 0 || !errors[i].is_finite() || errors[i] > factor * best);
    (best, at)
}

/// The scene's camera orbited by `degrees` about world +Y through the point `distance` ahead
/// ([`scenes::Camera::orbited`]); frame 0 is the study's own view, bit for bit, so its ground
/// truth is a cache hit.
pub fn orbit(scene: &Scene, degrees: f32, distance: f32) -> Scene {
    let mut s = scene.clone();
    s.camera = scene.camera.orbited(degrees, distance);
    s
}

/// The scenes of the flicker frames: the base scene moved by frame k's step of the motion.
pub fn flicker_frames(
    study: &Study,
    scene: &Scene,
    point: &ScenePoint,
    f: &Flicker,
    quick: bool,
) -> Result<Vec<Scene>, StudyError> {
    let mut frames: Vec<Scene> = Vec::new();
    for k in 0..f.frames {
        frames.push(match &f.motion {
            Motion::Orbit { degrees, distance } => orbit(scene, k as f32 * degrees, *distance),
            Motion::Shift { .. } if k == 0 => scene.clone(),
            Motion::Shift { .. } => {
                let mut edits = point.overrides.clone();
                edits.extend(shifted(&f.motion, k));
                prepare(study, quick, &edits)?.0
            }
        });
    }
    Ok(frames)
}

/// Flicker of every variant (of the first scene point, whose scene, oracle settings and
/// point `base` are) over `f.frames` frames of its motion; ground truths cached like the
/// study's own, frame 0 being the study's own view.
pub fn flicker(
    study: &Study,
    rasters: &Rasters,
    (scene, settings, point): (&Scene, RenderSettings, &ScenePoint),
    variants: &[Variant],
    f: &Flicker,
    opts: &RunOptions,
) -> Result<Vec<FlickerResult>, StudyError> {
    let frame_opts = RunOptions {
        out_dir: opts.out_dir.join("flicker"),
        ..opts.clone()
    };
    std::fs::create_dir_all(&frame_opts.out_dir)
        .map_err(|e| StudyError::Run(format!("{}: {e}", frame_opts.out_dir.display())))?;
    let frames = flicker_frames(study, scene, point, f, opts.quick)?;
    let mut refs = Vec::new();
    let mut interiors = Vec::new();
    for (k, s) in frames.iter().enumerate() {
        let (img, _) = ground_truth(s, settings, &frame_opts, &format!("frame-{k}"))?;
        let image = RgbImage::from_layered(&img, "flicker ground truth").map_err(StudyError::Run)?;
        // Without a noise estimate (metrics::missing_noise_estimate) the floor is 0.
        let var = image
            .variance
            .unwrap_or_else(|| vec![Vec3::ZERO; image.rgb.len()]);
        refs.push((image.rgb, var));
        interiors.push(Mask::interior(&img));
    }
    let no_pixels = || {
        StudyError::Input(format!(
            "{}: [stability.flicker]: no pixel is interior in two consecutive frames, so flicker cannot be measured",
            study.path.display()
        ))
    };
    let noise_floor = mean_over_pairs(&refs, &interiors, |k, i| {
        let s = (refs[k].1[i] + refs[k + 1].1[i])
            .max(Vec3::ZERO)
            .as_dvec3()
            .powf(0.5);
        s * (2.0 / std::f64::consts::PI).sqrt()
    })
    .ok_or_else(no_pixels)?;
    let mut out = Vec::new();
    for v in variants {
        let mut errors = Vec::new();
        for (k, (s, (r, _))) in frames.iter().zip(&refs).enumerate() {
            let key = RasterKey::flicker(v.id(), k);
            let img = rasters
                .render(&key, s, &flicker_raster_settings(study, s, v), opts)?
                .image;
            let a = img
                .rgb("")
                .ok_or_else(|| StudyError::Run("raster image without RGB".into()))?;
            errors.push(
                a.iter()
                    .zip(r)
                    .map(|(a, r)| a.as_dvec3() - r.as_dvec3())
                    .collect::<Vec<DVec3>>(),
            );
        }
        let value = mean_over_pairs(&refs, &interiors, |k, i| (errors[k + 1][i] - errors[k][i]).abs())
            .ok_or_else(no_pixels)?;
        out.push(FlickerResult {
            variant: v.label(),
            motion: f.motion.describe(),
            frames: f.frames,
            flicker: value,
            noise_floor,
        });
    }
    Ok(out)
}

/// Mean over consecutive frame pairs k, pixels i interior in both frames and channels of
/// `delta(k, i) / (|r_k,i| + ε)`, in f64; NaN when a term is not finite (never skipped: a
/// skipped NaN pixel would make a broken method look stable); None when no pixel counts.
fn mean_over_pairs(
    refs: &[(Vec<Vec3>, Vec<Vec3>)],
    interiors: &[Mask],
    delta: impl Fn(usize, usize) -> DVec3,
) -> Option<f64> {
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for k in 0..refs.len() - 1 {
        for i in 0..refs[k].0.len() {
            if !(interiors[k].selects(i) && interiors[k + 1].selects(i)) {
                continue;
            }
            let r = refs[k].0[i].abs().as_dvec3() + DVec3::splat(f64::from(RELATIVE_EPSILON));
            sum += (delta(k, i) / r).element_sum() / 3.0;
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flicker_of_a_nan_pixel_is_nan_and_of_no_pixel_is_none() {
        let refs = vec![(vec![Vec3::splat(0.5); 2], vec![Vec3::ZERO; 2]); 2];
        let all = vec![Mask::all(2, 1); 2];
        let errors = [
            [DVec3::ZERO, DVec3::ZERO],
            [DVec3::splat(0.051), DVec3::splat(f64::NAN)],
        ];
        let delta = |k: usize, i: usize| (errors[k + 1][i] - errors[k][i]).abs();
        // One pixel moved by 0.051 / 0.51 = 0.1, the other is NaN: NaN, not 0.1.
        assert!(mean_over_pairs(&refs, &all, delta).is_some_and(f64::is_nan));
        let finite = |k: usize, i: usize| if i == 0 { delta(k, i) } else { DVec3::ZERO };
        let v = mean_over_pairs(&refs, &all, finite).unwrap();
        assert!((v - 0.05).abs() < 1e-7, "{v}");
        // Huge but finite errors stay finite in f64 (their f32 difference overflowed).
        let big = |_: usize, _: usize| DVec3::splat(2.0 * f64::from(f32::MAX));
        assert!(mean_over_pairs(&refs, &all, big).is_some_and(f64::is_finite));
        let none = vec![
            Mask {
                pixels: vec![false; 2],
                ..Mask::all(2, 1)
            };
            2
        ];
        assert_eq!(mean_over_pairs(&refs, &none, delta), None);
    }

    #[test]
    fn breakpoint_is_the_first_value_past_k_times_best() {
        let errors = [1e-5, 2e-5, 3e-5, 9e-5, 1e-3];
        assert_eq!(breakpoint(&errors, &[0; 5], 4.0), (1e-5, Some(3)));
        assert_eq!(breakpoint(&errors, &[0; 5], 200.0), (1e-5, None));
        // NaN pixels break at once, whatever the error.
        assert_eq!(breakpoint(&errors, &[0, 1, 0, 0, 0], 200.0).1, Some(1));
    }
}
