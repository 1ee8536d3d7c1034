//! Delta lights and the environment → Mitsuba 3 emitters.
//!
//! `point` takes the intensity in W/sr; `spot` the on-axis intensity, `cutoff_angle` and
//! `beam_width` in degrees with the same linear-in-angle falloff as ours (probed: full
//! intensity up to the beam width, linear to zero at the cutoff, also for beam width 0 and
//! beam width = cutoff), pointing along its local +Z (`to_world` = lookat), with a projected
//! texture as its `texture` (a `bitmap` with the factor baked in; the frame's up is −up,
//! scenes::projection); `directional`
//! takes the irradiance on a surface facing it and the direction light travels to. Mitsuba
//! has no sun disk, so a directional light with an angular diameter is refused. Environment:
//! `constant`, or `envmap` with our image written as float EXR and the same `scale`; the
//! orientation and texel placement are the same by convention (docs/ARCHITECTURE.md,
//! scenes/src/model.rs `environment_lookup`), so no rotation is exported.

use glam::Vec3;
use scenes::{Environment, Light};

use super::{lookat, Asset, Exporter};
use crate::mitsuba::xml::Element;
use scenes::layered::LayeredImage;

/// File name of the exported environment map.
pub(super) const ENVIRONMENT_FILE: &str = "textures/environment.exr";

impl Exporter<'_> {
    /// The delta lights and the environment.
    pub(super) fn lights(&mut self) -> Vec<Element> {
        let scene = self.scene;
        let mut out: Vec<Element> = scene.lights.iter().filter_map(|l| self.light(l)).collect();
        if let Some(env) = &scene.environment {
            out.push(self.environment(env));
        }
        out
    }

    fn light(&mut self, light: &Light) -> Option<Element> {
        let el = match light {
            Light::Point {
                position, intensity, ..
            } => Element::plugin("emitter", "point")
                .child(Element::point("position", *position))
                .child(Element::rgb("intensity", *intensity)),
            Light::Spot {
                name,
                position,
                direction,
                intensity,
                cutoff_deg,
                beam_width_deg,
                projection,
            } => {
                // A projected texture's image up is our `up`; Mitsuba's uv runs along its
                // frame's x = up′ × axis and y, so up′ = −up gives the same uv
                // (scenes::projection). Without one the frame is any.
                let up = match projection {
                    Some(p) => -p.up,
                    None if direction.y.abs() < 0.9 => Vec3::Y,
                    None => Vec3::X,
                };
                let mut el = Element::plugin("emitter", "spot")
                    .child(Element::rgb("intensity", *intensity))
                    .child(Element::float("cutoff_angle", *cutoff_deg))
                    .child(Element::float("beam_width", *beam_width_deg))
                    .child(Element::new("transform").attr("name", "to_world").child(lookat(
                        *position,
                        *position + *direction,
                        up,
                    )));
                if let Some(p) = projection {
                    el = el.child(self.rgb_input(
                        "texture",
                        &p.texture,
                        &format!("light `{name}`: projected texture"),
                    )?);
                }
                el
            }
            Light::Directional {
                name,
                direction,
                irradiance,
                angular_diameter_deg,
            } => {
                if *angular_diameter_deg > 0.0 {
                    self.refuse(format!(
                        "light `{name}`: directional light with an angular diameter of {angular_diameter_deg}° \
                         (a sun disk); Mitsuba's `directional` is a delta light"
                    ));
                    return None;
                }
                Element::plugin("emitter", "directional")
                    .child(Element::vector("direction", *direction))
                    .child(Element::rgb("irradiance", *irradiance))
            }
        };
        Some(el.with_comment(format!("light `{}`", light.name())))
    }

    fn environment(&mut self, env: &Environment) -> Element {
        match env {
            Environment::Constant { radiance } => {
                Element::plugin("emitter", "constant").child(Element::rgb("radiance", *radiance))
            }
            Environment::Map { texture, scale } => {
                let tex = &self.scene.textures[*texture];
                let texels: Vec<Vec3> = tex.texels.iter().map(|t| t.truncate()).collect();
                let mut image = LayeredImage::new(tex.width, tex.height);
                image.push_rgb("", &texels);
                self.assets
                    .push((ENVIRONMENT_FILE.to_string(), Asset::Exr(image)));
                Element::plugin("emitter", "envmap")
                    .child(Element::string("filename", ENVIRONMENT_FILE))
                    .child(Element::float("scale", *scale))
            }
        }
        .with_comment("environment")
    }
}
