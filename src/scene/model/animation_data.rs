//! Animation as data: keyframe channels read from a file, checked once when built. Sampling
//! them over time is `scene::animation`'s job.

use glam::{Quat, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Step,
    Linear,
    CubicSpline,
}

/// Keyframe values. For CUBICSPLINE there are three per key, in the file's order:
/// in-tangent, value, out-tangent.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelValues {
    /// Translation or scale.
    Vec3(Vec<Vec3>),
    /// Rotation; values are unit quaternions (tangents are not normalised).
    Rotation(Vec<Quat>),
}

impl ChannelValues {
    fn len(&self) -> usize {
        match self {
            ChannelValues::Vec3(v) => v.len(),
            ChannelValues::Rotation(v) => v.len(),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// Target node index.
    pub node: usize,
    pub property: Property,
    pub interpolation: Interpolation,
    /// Key times in seconds, finite and strictly increasing.
    pub times: Vec<f32>,
    pub values: ChannelValues,
}

impl Channel {
    /// Builds a channel, checking what sampling relies on: at least one key, finite strictly
    /// increasing times, values of the kind the property needs, one value per key (three for
    /// CUBICSPLINE), finite values. Rotation values are normalised. The error says what is wrong
    /// without naming the file (the loader adds that).
    pub fn new(
        node: usize,
        property: Property,
        interpolation: Interpolation,
        times: Vec<f32>,
        values: ChannelValues,
    ) -> std::result::Result<Channel, String> {
        if times.is_empty() {
            return Err("no keyframes".into());
        }
        for (i, t) in times.iter().enumerate() {
            if !t.is_finite() {
                return Err(format!("key time {i} is {t}, not a finite number"));
            }
        }
        for (i, pair) in times.windows(2).enumerate() {
            if let [a, b] = pair {
                if b <= a {
                    return Err(format!(
                        "key times are not strictly increasing: key {} is at {b} s after key {i} \
                         at {a} s",
                        i + 1
                    ));
                }
            }
        }
        let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        let expected = times.len() * per_key;
        if values.len() != expected {
            return Err(format!(
                "{} key times need {expected} output values for {interpolation:?}, found {}",
                times.len(),
                values.len()
            ));
        }
        let values = match (property, values) {
            (Property::Translation | Property::Scale, ChannelValues::Vec3(v)) => {
                if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                    return Err(format!("output value {i} is not finite"));
                }
                ChannelValues::Vec3(v)
            }
            (Property::Rotation, ChannelValues::Rotation(v)) => {
                if let Some(i) = v.iter().position(|q| !q.is_finite()) {
                    return Err(format!("output value {i} is not finite"));
                }
                let mut v = v;
                for (i, q) in v.iter_mut().enumerate() {
                    let is_tangent = per_key == 3 && i % 3 != 1;
                    if !is_tangent {
                        let len = q.length();
                        if len < 1e-6 {
                            return Err(format!("rotation value {i} is a zero quaternion"));
                        }
                        *q = *q / len;
                    }
                }
                ChannelValues::Rotation(v)
            }
            (p, _) => return Err(format!("{p:?} channel with values of the wrong kind")),
        };
        Ok(Channel { node, property, interpolation, times, values })
    }

    /// Time of the last key.
    pub fn end_time(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Animation {
    pub name: Option<String>,
    pub channels: Vec<Channel>,
    /// Seconds: the latest last key of any channel.
    pub duration: f32,
}
