//! Animation channels read from the file: target, interpolation, key times and values, each
//! channel checked by `Channel::new`. Morph-target weight channels are skipped.

use glam::{Quat, Vec3};
use gltf::json;
use json::accessor::{ComponentType as C, Type as T};

use super::loader::{checked, label, Loader, FLOAT_OR_NORM};
use crate::error::Result;
use crate::scene::model::{Animation, Channel, ChannelValues, Interpolation, Property};

impl Loader<'_> {
    pub(super) fn animations(&mut self) -> Result<Vec<Animation>> {
        let mut out = Vec::with_capacity(self.root.animations.len());
        for (a, anim) in self.root.animations.iter().enumerate() {
            let what = label("animation", a, anim.name.as_deref());
            let mut channels = Vec::with_capacity(anim.channels.len());
            let mut skipped_weights = 0;
            for (c, channel) in anim.channels.iter().enumerate() {
                let node = channel.target.node.value();
                let property = match checked(&channel.target.path) {
                    Some(json::animation::Property::Translation) => Property::Translation,
                    Some(json::animation::Property::Rotation) => Property::Rotation,
                    Some(json::animation::Property::Scale) => Property::Scale,
                    Some(json::animation::Property::MorphTargetWeights) => {
                        skipped_weights += 1;
                        continue;
                    }
                    None => return Err(self.fail(format!("{what} channel {c}: bad target path"))),
                };
                let here = format!("{what} channel {c} (node {node} {property:?})");
                if node >= self.root.nodes.len() {
                    return Err(self.fail(format!("{here}: node {node} does not exist")));
                }
                let s = channel.sampler.value();
                let sampler =
                    anim.samplers.get(s).ok_or_else(|| self.fail(format!("{here}: sampler {s} does not exist")))?;
                let interpolation = match checked(&sampler.interpolation) {
                    Some(json::animation::Interpolation::Step) => Interpolation::Step,
                    Some(json::animation::Interpolation::CubicSpline) => Interpolation::CubicSpline,
                    _ => Interpolation::Linear,
                };
                let input = sampler.input.value();
                let stored =
                    self.root.accessors.get(input).is_some_and(|a| a.buffer_view.is_some() || a.sparse.is_some());
                if !stored {
                    // Valid glTF, but zero-filled key times: the file does not say when anything
                    // happens.
                    self.warnings.push(format!(
                        "{here}: its key times (accessor {input}) have no bufferView, so no data; channel ignored"
                    ));
                    continue;
                }
                let times = self.floats(input, &format!("{here} input"), T::Scalar, &[C::F32])?;
                let output = format!("{here} output");
                let values = match property {
                    Property::Rotation => {
                        let flat = self.floats(sampler.output.value(), &output, T::Vec4, FLOAT_OR_NORM)?;
                        ChannelValues::Rotation(flat.chunks_exact(4).map(Quat::from_slice).collect())
                    }
                    _ => {
                        let flat = self.floats(sampler.output.value(), &output, T::Vec3, &[C::F32])?;
                        ChannelValues::Vec3(flat.chunks_exact(3).map(Vec3::from_slice).collect())
                    }
                };
                let channel = Channel::new(node, property, interpolation, times, values)
                    .map_err(|e| self.fail(format!("{here} sampler {s}: {e}")))?;
                channels.push(channel);
            }
            if skipped_weights > 0 {
                self.warnings.push(format!("{what}: {skipped_weights} morph-target weight channels skipped"));
            }
            let duration = channels.iter().map(Channel::end_time).fold(0.0, f32::max);
            out.push(Animation { name: anim.name.clone(), channels, duration });
        }
        Ok(out)
    }
}
