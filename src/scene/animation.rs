//! Node animation: sampling keyframe channels (their data lives in `model`), as pure functions
//! of time.
//!
//! Sampling follows glTF 2.0 Appendix C: STEP holds the previous key, LINEAR lerps translation and
//! scale and slerps rotation (shortest path), CUBICSPLINE is the Hermite spline whose tangents are
//! scaled by the key interval. Before the first key a channel gives its first value, after the last
//! key its last value. Morph-target weights are not animated (the loader skips those channels).

use glam::{Quat, Vec3, Vec4};

use super::model::{Channel, ChannelValues, Interpolation, Model, Property, Transform};
use crate::error::{Error, Result};

/// One sampled property value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sample {
    Translation(Vec3),
    Rotation(Quat),
    Scale(Vec3),
}

/// What happens to times outside `[0, duration]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeMode {
    /// Hold the first / last key (the tests' mode: the viewer and profiles loop).
    #[cfg(test)]
    Clamp,
    /// `t mod duration` (negative times wrap too).
    Loop,
}

/// Where `t` falls among the keys.
enum Span {
    /// Before the first key, after the last, or a single key: hold key `i`.
    Hold(usize),
    /// Between key `i` and `i + 1`, `u` in [0, 1), `dt` the key interval.
    Between { i: usize, u: f32, dt: f32 },
}

fn locate(times: &[f32], t: f32) -> Span {
    let n = times.len();
    let first = times.first().copied().unwrap_or(0.0);
    let last = times.last().copied().unwrap_or(0.0);
    if n < 2 || t.is_nan() || t <= first {
        return Span::Hold(0);
    }
    if t >= last {
        return Span::Hold(n - 1);
    }
    // First key strictly after t; t > first so it is >= 1, t < last so it is <= n - 1.
    let next = times.partition_point(|&k| k <= t).clamp(1, n - 1);
    let i = next - 1;
    let (Some(&t0), Some(&t1)) = (times.get(i), times.get(next)) else {
        return Span::Hold(0);
    };
    let dt = t1 - t0;
    let u = if dt > 0.0 { (t - t0) / dt } else { 0.0 };
    Span::Between { i, u, dt }
}

/// glTF cubic Hermite: `v0, v1` key values, `b0` the out-tangent of key 0, `a1` the in-tangent of
/// key 1, both scaled by the interval `dt`.
fn hermite(v0: Vec4, b0: Vec4, v1: Vec4, a1: Vec4, u: f32, dt: f32) -> Vec4 {
    let u2 = u * u;
    let u3 = u2 * u;
    v0 * (2.0 * u3 - 3.0 * u2 + 1.0)
        + b0 * (dt * (u3 - 2.0 * u2 + u))
        + v1 * (-2.0 * u3 + 3.0 * u2)
        + a1 * (dt * (u3 - u2))
}

/// Samples keyframe values (read through `at`, as Vec4s) at the located span. `None` if the
/// value list is too short for the key count (only possible for a channel built without
/// `Channel::new`).
fn sample_vec4(at: impl Fn(usize) -> Option<Vec4>, interpolation: Interpolation, span: Span) -> Option<Vec4> {
    let cubic = interpolation == Interpolation::CubicSpline;
    // Index of key k's value: the middle of its triple for CUBICSPLINE.
    let value = |k: usize| at(if cubic { 3 * k + 1 } else { k });
    match span {
        Span::Hold(k) => value(k),
        Span::Between { i, u, dt } => match interpolation {
            Interpolation::Step => value(i),
            Interpolation::Linear => Some(value(i)?.lerp(value(i + 1)?, u)),
            Interpolation::CubicSpline => {
                let b0 = at(3 * i + 2)?;
                let a1 = at(3 * (i + 1))?;
                Some(hermite(value(i)?, b0, value(i + 1)?, a1, u, dt))
            }
        },
    }
}

/// The channel's value at time `t` (seconds, not wrapped: see `pose_at` for looping). `None`
/// only for a channel with no keys or too few values.
pub fn sample_channel(channel: &Channel, t: f32) -> Option<Sample> {
    let span = locate(&channel.times, t);
    match &channel.values {
        ChannelValues::Vec3(v) => {
            let at = |k: usize| v.get(k).map(|x| x.extend(0.0));
            let s = sample_vec4(at, channel.interpolation, span)?.truncate();
            Some(match channel.property {
                Property::Scale => Sample::Scale(s),
                _ => Sample::Translation(s),
            })
        }
        ChannelValues::Rotation(q) => {
            let rotation = match (channel.interpolation, span) {
                // Slerp rather than the lerp in `sample_vec4`: constant angular speed, and the
                // shortest path when neighbouring keys lie in opposite hemispheres.
                (Interpolation::Linear, Span::Between { i, u, .. }) => {
                    let a = q.get(i)?.normalize();
                    let b = q.get(i + 1)?.normalize();
                    a.slerp(b, u)
                }
                (interpolation, span) => {
                    let at = |k: usize| q.get(k).map(|x| Vec4::from(*x));
                    let v = sample_vec4(at, interpolation, span)?;
                    let len = v.length();
                    if len > 1e-12 && len.is_finite() {
                        Quat::from_vec4(v / len)
                    } else {
                        Quat::IDENTITY
                    }
                }
            };
            Some(Sample::Rotation(rotation))
        }
    }
}

/// Maps a caller's time into the animation's time line.
pub fn wrap_time(t: f32, duration: f32, mode: TimeMode) -> f32 {
    if !t.is_finite() || duration.is_nan() || duration <= 0.0 {
        return 0.0;
    }
    match mode {
        #[cfg(test)]
        TimeMode::Clamp => t.clamp(0.0, duration),
        TimeMode::Loop => {
            let w = t.rem_euclid(duration);
            // rem_euclid can round up to `duration` itself for tiny negative t.
            if w >= duration {
                0.0
            } else {
                w
            }
        }
    }
}

/// Rest-pose local transforms of every node.
pub fn rest_pose(model: &Model) -> Vec<Transform> {
    model.nodes.iter().map(|n| n.local).collect()
}

/// Local transforms of all nodes at time `t` of animation `animation_index`: animated
/// properties take their sampled values, everything else keeps the rest pose.
pub fn pose_at(model: &Model, animation_index: usize, t: f32, mode: TimeMode) -> Result<Vec<Transform>> {
    let animation = model.animations.get(animation_index).ok_or_else(|| {
        Error::InvalidInput(format!(
            "animation {animation_index} does not exist (the model has {})",
            model.animations.len()
        ))
    })?;
    let t = wrap_time(t, animation.duration, mode);
    let mut pose = rest_pose(model);
    for channel in &animation.channels {
        let (Some(local), Some(sample)) = (pose.get_mut(channel.node), sample_channel(channel, t)) else {
            continue;
        };
        match sample {
            Sample::Translation(v) => local.translation = v,
            Sample::Rotation(q) => local.rotation = q,
            Sample::Scale(v) => local.scale = v,
        }
    }
    Ok(pose)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::model::Animation;

    fn translation_channel(interpolation: Interpolation, times: &[f32], v: &[Vec3]) -> Channel {
        Channel::new(0, Property::Translation, interpolation, times.to_vec(), ChannelValues::Vec3(v.to_vec())).unwrap()
    }

    fn translation(channel: &Channel, t: f32) -> Vec3 {
        match sample_channel(channel, t) {
            Some(Sample::Translation(v)) => v,
            other => panic!("expected a translation, got {other:?}"),
        }
    }

    fn rotation(channel: &Channel, t: f32) -> Quat {
        match sample_channel(channel, t) {
            Some(Sample::Rotation(q)) => q,
            other => panic!("expected a rotation, got {other:?}"),
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    #[test]
    fn step_holds_the_previous_key() {
        let c = translation_channel(Interpolation::Step, &[1.0, 2.0, 4.0], &[Vec3::X, Vec3::Y, Vec3::Z]);
        assert_eq!(translation(&c, 0.0), Vec3::X, "before the first key");
        assert_eq!(translation(&c, 1.0), Vec3::X);
        assert_eq!(translation(&c, 1.999), Vec3::X);
        assert_eq!(translation(&c, 2.0), Vec3::Y);
        assert_eq!(translation(&c, 3.9), Vec3::Y);
        assert_eq!(translation(&c, 4.0), Vec3::Z);
        assert_eq!(translation(&c, 100.0), Vec3::Z, "after the last key");
    }

    #[test]
    fn linear_translation_halfway_and_outside() {
        let c = translation_channel(
            Interpolation::Linear,
            &[1.0, 3.0],
            &[Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, -4.0, 8.0)],
        );
        assert!(close(translation(&c, 2.0), Vec3::new(1.0, -2.0, 4.0)));
        assert!(close(translation(&c, 1.5), Vec3::new(0.5, -1.0, 2.0)));
        assert_eq!(translation(&c, -5.0), Vec3::ZERO);
        assert_eq!(translation(&c, 7.0), Vec3::new(2.0, -4.0, 8.0));
    }

    #[test]
    fn single_key_is_constant() {
        let c = translation_channel(Interpolation::Linear, &[0.5], &[Vec3::ONE]);
        for t in [-1.0, 0.5, 9.0] {
            assert_eq!(translation(&c, t), Vec3::ONE);
        }
    }

    #[test]
    fn linear_rotation_slerps_90_degrees_to_45_at_half() {
        let q0 = Quat::IDENTITY;
        let q1 = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let c = Channel::new(
            0,
            Property::Rotation,
            Interpolation::Linear,
            vec![0.0, 1.0],
            ChannelValues::Rotation(vec![q0, q1]),
        )
        .unwrap();
        let q = rotation(&c, 0.5);
        let (axis, angle) = q.to_axis_angle();
        assert!((angle - std::f32::consts::FRAC_PI_4).abs() < 1e-5, "angle {angle}");
        assert!(close(axis, Vec3::Y), "axis {axis}");
        // A quarter of the way is 22.5 degrees: slerp keeps angular speed constant.
        let (_, angle) = rotation(&c, 0.25).to_axis_angle();
        assert!((angle - std::f32::consts::FRAC_PI_8).abs() < 1e-5, "angle {angle}");
    }

    #[test]
    fn linear_rotation_takes_the_shortest_path() {
        // -q1 is the same rotation as q1; interpolating towards it must not go the long way.
        let q1 = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let c = Channel::new(
            0,
            Property::Rotation,
            Interpolation::Linear,
            vec![0.0, 1.0],
            ChannelValues::Rotation(vec![Quat::IDENTITY, -q1]),
        )
        .unwrap();
        let q = rotation(&c, 0.5);
        let expected = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        assert!(q.dot(expected).abs() > 1.0 - 1e-6, "{q} vs {expected}");
        assert!((q.length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cubic_spline_matches_hermite_by_hand() {
        // Keys at t = 1 and t = 3 (dt = 2), scalar values in x; nonzero tangents.
        // v0 = 1, out-tangent b0 = 2; v1 = 5, in-tangent a1 = -1.
        let (v0, b0, v1, a1) = (1.0f32, 2.0f32, 5.0f32, -1.0f32);
        let values = vec![
            Vec3::new(9.0, 0.0, 0.0), // in-tangent of key 0: unused
            Vec3::new(v0, 0.0, 0.0),
            Vec3::new(b0, 0.0, 0.0),
            Vec3::new(a1, 0.0, 0.0),
            Vec3::new(v1, 0.0, 0.0),
            Vec3::new(9.0, 0.0, 0.0), // out-tangent of key 1: unused
        ];
        let c = translation_channel(Interpolation::CubicSpline, &[1.0, 3.0], &values);
        // At t = 2: s = 0.5, dt = 2.
        // h00 = 2s^3 - 3s^2 + 1 = 0.5, h10 = s^3 - 2s^2 + s = 0.125,
        // h01 = -2s^3 + 3s^2 = 0.5, h11 = s^3 - s^2 = -0.125.
        // p = 0.5*1 + 0.125*2*2 + 0.5*5 + (-0.125)*2*(-1) = 0.5 + 0.5 + 2.5 + 0.25 = 3.75
        assert!((translation(&c, 2.0).x - 3.75).abs() < 1e-6);
        // At t = 1.5: s = 0.25. h00 = 0.84375, h10 = 0.140625, h01 = 0.15625, h11 = -0.046875.
        // p = 0.84375 + 0.140625*4 + 0.15625*5 + (-0.046875)*(-2) = 2.28125
        assert!((translation(&c, 1.5).x - 2.28125).abs() < 1e-6);
        // Key values at and beyond the ends (not the tangents).
        assert_eq!(translation(&c, 1.0).x, v0);
        assert_eq!(translation(&c, 0.0).x, v0);
        assert_eq!(translation(&c, 3.0).x, v1);
        assert_eq!(translation(&c, 10.0).x, v1);
    }

    #[test]
    fn cubic_spline_rotation_is_normalised() {
        let q0 = Quat::IDENTITY;
        let q1 = Quat::from_rotation_x(1.0);
        let t = Quat::from_xyzw(0.3, 0.1, 0.0, 0.2);
        let c = Channel::new(
            0,
            Property::Rotation,
            Interpolation::CubicSpline,
            vec![0.0, 1.0],
            ChannelValues::Rotation(vec![t, q0, t, t, q1, t]),
        )
        .unwrap();
        for i in 0..=10 {
            let q = rotation(&c, i as f32 / 10.0);
            assert!((q.length() - 1.0).abs() < 1e-5, "{q}");
        }
        assert!(rotation(&c, 1.0).dot(q1).abs() > 1.0 - 1e-6);
    }

    #[test]
    fn rejects_times_that_do_not_increase() {
        let bad = [vec![0.0, 1.0, 1.0], vec![0.0, 2.0, 1.0], vec![0.0, f32::NAN]];
        for times in bad {
            let n = times.len();
            let err = Channel::new(
                0,
                Property::Scale,
                Interpolation::Linear,
                times.clone(),
                ChannelValues::Vec3(vec![Vec3::ONE; n]),
            )
            .unwrap_err();
            assert!(err.contains("strictly increasing") || err.contains("not a finite"), "{times:?}: {err}");
        }
    }

    #[test]
    fn rejects_wrong_value_counts_and_kinds() {
        let err = Channel::new(
            0,
            Property::Translation,
            Interpolation::CubicSpline,
            vec![0.0, 1.0],
            ChannelValues::Vec3(vec![Vec3::ZERO; 2]),
        )
        .unwrap_err();
        assert!(err.contains("need 6"), "{err}");
        let err = Channel::new(
            0,
            Property::Rotation,
            Interpolation::Linear,
            vec![0.0],
            ChannelValues::Vec3(vec![Vec3::ZERO]),
        )
        .unwrap_err();
        assert!(err.contains("wrong kind"), "{err}");
    }

    #[test]
    fn wrap_time_loops_and_clamps() {
        assert_eq!(wrap_time(2.5, 2.0, TimeMode::Loop), 0.5);
        assert_eq!(wrap_time(-0.5, 2.0, TimeMode::Loop), 1.5);
        assert_eq!(wrap_time(2.5, 2.0, TimeMode::Clamp), 2.0);
        assert_eq!(wrap_time(-1.0, 2.0, TimeMode::Clamp), 0.0);
        assert_eq!(wrap_time(f32::NAN, 2.0, TimeMode::Loop), 0.0);
        assert_eq!(wrap_time(3.0, 0.0, TimeMode::Loop), 0.0);
    }

    #[test]
    fn pose_at_overrides_only_animated_properties() {
        use crate::scene::model::Node;
        let rest = Transform {
            translation: Vec3::new(1.0, 2.0, 3.0),
            rotation: Quat::from_rotation_x(0.3),
            scale: Vec3::splat(2.0),
        };
        let model = Model {
            nodes: vec![Node { local: rest, ..Node::default() }, Node { local: rest, ..Node::default() }],
            animations: vec![Animation {
                name: None,
                channels: vec![Channel::new(
                    1,
                    Property::Translation,
                    Interpolation::Linear,
                    vec![0.0, 2.0],
                    ChannelValues::Vec3(vec![Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)]),
                )
                .unwrap()],
                duration: 2.0,
            }],
            ..Model::default()
        };
        let pose = pose_at(&model, 0, 1.0, TimeMode::Clamp).unwrap();
        assert_eq!(pose[0], rest);
        assert_eq!(pose[1].translation, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(pose[1].rotation, rest.rotation);
        assert_eq!(pose[1].scale, rest.scale);
        // Looping: t = 3 is t = 1 again; clamping: t = 3 is the end.
        let looped = pose_at(&model, 0, 3.0, TimeMode::Loop).unwrap();
        assert_eq!(looped[1].translation, Vec3::new(2.0, 0.0, 0.0));
        let clamped = pose_at(&model, 0, 3.0, TimeMode::Clamp).unwrap();
        assert_eq!(clamped[1].translation, Vec3::new(4.0, 0.0, 0.0));
        assert!(pose_at(&model, 1, 0.0, TimeMode::Clamp).is_err());
    }
}
