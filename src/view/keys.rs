//! Held keys as motion, the same in the viewer and the CAVE master's window: two keys make an
//! axis, and the arrows with page up and down move the light.

use glam::Vec3;
use winit::keyboard::KeyCode;

/// +1 while `plus` is held, -1 while `minus` is, 0 for both or neither.
pub fn axis(held: &dyn Fn(KeyCode) -> bool, plus: KeyCode, minus: KeyCode) -> f32 {
    f32::from(u8::from(held(plus))) - f32::from(u8::from(held(minus)))
}

/// The light's motion: right and left arrows along x, page up and down along y, the down and
/// up arrows along z (toward the viewer and away).
pub fn light_motion(held: &dyn Fn(KeyCode) -> bool) -> Vec3 {
    Vec3::new(
        axis(held, KeyCode::ArrowRight, KeyCode::ArrowLeft),
        axis(held, KeyCode::PageUp, KeyCode::PageDown),
        axis(held, KeyCode::ArrowDown, KeyCode::ArrowUp),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opposite_keys_cancel_and_each_alone_gives_its_sign() {
        let keys = |down: &'static [KeyCode]| move |k: KeyCode| down.contains(&k);
        assert_eq!(
            axis(&keys(&[KeyCode::KeyD]), KeyCode::KeyD, KeyCode::KeyA),
            1.0
        );
        assert_eq!(
            axis(&keys(&[KeyCode::KeyA]), KeyCode::KeyD, KeyCode::KeyA),
            -1.0
        );
        assert_eq!(
            axis(
                &keys(&[KeyCode::KeyA, KeyCode::KeyD]),
                KeyCode::KeyD,
                KeyCode::KeyA
            ),
            0.0
        );
        assert_eq!(
            light_motion(&keys(&[
                KeyCode::ArrowLeft,
                KeyCode::PageUp,
                KeyCode::ArrowUp
            ])),
            Vec3::new(-1.0, 1.0, -1.0)
        );
        assert_eq!(light_motion(&keys(&[])), Vec3::ZERO);
    }
}
