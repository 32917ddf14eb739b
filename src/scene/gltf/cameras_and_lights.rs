//! What nodes carry besides meshes: cameras and KHR_lights_punctual lights.

use glam::Vec3;
use gltf::json;

use super::loader::{checked, label, Loader};
use crate::error::Result;
use crate::scene::model::{Camera, Light, LightKind, Projection};

impl Loader<'_> {
    pub(super) fn cameras(&mut self) -> Result<Vec<Camera>> {
        use json::camera::Type as CameraType;
        let mut out = Vec::with_capacity(self.root.cameras.len());
        for (i, cam) in self.root.cameras.iter().enumerate() {
            let what = label("camera", i, cam.name.as_deref());
            let projection = match (checked(&cam.type_), &cam.perspective, &cam.orthographic) {
                (Some(CameraType::Perspective), Some(p), _) => {
                    Projection::Perspective { yfov: p.yfov, aspect_ratio: p.aspect_ratio, znear: p.znear, zfar: p.zfar }
                }
                (Some(CameraType::Orthographic), _, Some(o)) => {
                    Projection::Orthographic { xmag: o.xmag, ymag: o.ymag, znear: o.znear, zfar: o.zfar }
                }
                _ => return Err(self.fail(format!("{what}: type does not match its perspective/orthographic block"))),
            };
            out.push(Camera { name: cam.name.clone(), projection });
        }
        Ok(out)
    }

    /// Whether light `index` is directional, point or spot (a later spec may add types, which
    /// are valid glTF; nodes then ignore the light).
    pub(super) fn light_type_is_known(&self, index: usize) -> bool {
        let lights = self.root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref());
        lights.and_then(|l| l.lights.get(index)).is_some_and(|l| checked(&l.type_).is_some())
    }

    pub(super) fn lights(&self) -> Vec<Light> {
        use json::extensions::scene::khr_lights_punctual::Type as LightType;
        let Some(ext) = self.root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()) else {
            return Vec::new();
        };
        ext.lights
            .iter()
            .map(|l| Light {
                name: l.name.clone(),
                kind: match (checked(&l.type_), &l.spot) {
                    (Some(LightType::Spot), Some(spot)) => LightKind::Spot {
                        inner_cone_angle: spot.inner_cone_angle,
                        outer_cone_angle: spot.outer_cone_angle,
                    },
                    (Some(LightType::Directional), _) => LightKind::Directional,
                    _ => LightKind::Point,
                },
                color: Vec3::from_array(l.color),
                intensity: l.intensity,
                range: l.range,
            })
            .collect()
    }
}
