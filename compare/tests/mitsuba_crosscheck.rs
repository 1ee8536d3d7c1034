//! Every built-in scene that Mitsuba 3 can express agrees with Mitsuba under the per-pixel
//! z-test, at a CI-friendly 64×64 and 256 spp; the others are listed in README.md
//! ("Mitsuba cross-check") and refused with the reason given there.

mod mitsuba_support;

use std::path::Path;

use compare::mitsuba::export;
use compare::mitsuba::runner::Variant;
use mitsuba_support::{at, builtin, check};

/// Built-in scenes cross-checked below.
const CROSSCHECKED: &[&str] = &["cornell-box", "mirror-sphere", "soft-shadow"];

/// Built-in scenes Mitsuba cannot express, with a phrase of the refusal (README.md lists them).
const NOT_EXPRESSIBLE: &[(&str, &str)] = &[("suzanne", "metal_rough, used by")];

fn agrees(name: &str, variant: Variant, size: u32, spp: u32) {
    let scene = at(builtin(name), size, size);
    let c = check(
        &format!("{name}-{}", variant.name()),
        &scene,
        &scene,
        spp,
        variant,
    );
    assert!(
        c.ztest.pass,
        "{name}: the oracle and Mitsuba {} disagree: {:.3} % of pixel-channels fail (≤ 0.25 % allowed), \
         min p {:.2e}, relMSE {:.3e} vs noise {:.3e}; see {}",
        variant.name(),
        100.0 * (1.0 - c.ztest.passed_fraction),
        c.ztest.min_p,
        c.ztest.relmse,
        c.ztest.relmse_noise,
        c.oracle_exr.parent().unwrap_or(Path::new(".")).display()
    );
}

#[test]
fn cornell_box_agrees() {
    agrees("cornell-box", Variant::LlvmAdRgb, 64, 256);
}

#[test]
fn mirror_sphere_agrees() {
    agrees("mirror-sphere", Variant::LlvmAdRgb, 64, 256);
}

#[test]
fn soft_shadow_agrees() {
    agrees("soft-shadow", Variant::LlvmAdRgb, 64, 256);
}

#[test]
fn soft_shadow_agrees_with_scalar_variant() {
    agrees("soft-shadow", Variant::ScalarRgb, 32, 128);
}

#[test]
fn every_builtin_scene_is_crosschecked_or_listed() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("scenes/ is readable")
        .filter_map(|e| e.ok()?.path().file_name()?.to_str().map(String::from))
        .filter_map(|f| f.strip_suffix(".toml").map(String::from))
        .filter(|stem| stem != "Cargo")
        .collect();
    names.sort();
    for name in &names {
        let outcome = export::export(&builtin(name));
        let listed = NOT_EXPRESSIBLE.iter().find(|(n, _)| n == name);
        match (outcome, listed) {
            (Ok(_), None) => assert!(
                CROSSCHECKED.contains(&name.as_str()),
                "scenes/{name}.toml is expressible in Mitsuba but has no cross-check test here"
            ),
            (Ok(_), Some(_)) => panic!("scenes/{name}.toml is listed as not expressible, but it exports"),
            (Err(e), Some((_, why))) => assert!(
                e.to_string().contains(why),
                "scenes/{name}.toml: refused for another reason than listed (`{why}`): {e}"
            ),
            (Err(e), None) => {
                panic!("scenes/{name}.toml cannot be cross-checked and is not listed in README.md: {e}")
            }
        }
    }
    for n in CROSSCHECKED {
        assert!(
            names.iter().any(|x| x == n),
            "CROSSCHECKED names scenes/{n}.toml, which does not exist"
        );
    }
}
