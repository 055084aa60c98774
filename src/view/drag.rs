//! A left-button drag: how far the pointer moved while the button was down.

#[derive(Clone, Copy, Debug, Default)]
pub struct Drag {
    dragging: bool,
    cursor: Option<(f32, f32)>,
}

impl Drag {
    /// The left button went down (true) or up.
    pub fn button(&mut self, pressed: bool) {
        self.dragging = pressed;
        self.cursor = None;
    }

    /// The pointer is now at `now`: how far it moved since the last position, while dragging.
    pub fn moved_to(&mut self, now: (f32, f32)) -> Option<(f32, f32)> {
        let moved = match (self.dragging, self.cursor) {
            (true, Some(last)) => Some((now.0 - last.0, now.1 - last.1)),
            _ => None,
        };
        self.cursor = Some(now);
        moved
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_moves_with_the_button_down_count() {
        let mut drag = Drag::default();
        assert_eq!(drag.moved_to((1.0, 1.0)), None);
        drag.button(true);
        assert_eq!(
            drag.moved_to((2.0, 3.0)),
            None,
            "the first position after the press"
        );
        assert_eq!(drag.moved_to((5.0, 1.0)), Some((3.0, -2.0)));
        drag.button(false);
        assert_eq!(drag.moved_to((9.0, 9.0)), None);
    }
}
