//! A rectangle placed on the ground: its local frame {A1, A2} turned by a heading about
//! E3, and its start point S. Used for the Euler three-rectangle paths of §2.5, whose
//! rectangles are oriented along e′1, e′2 (Figures 2.7–2.9).

use crate::rectangle::Rectangle;
use nalgebra::{Rotation3, Vector3};
use serde::{Deserialize, Serialize};

/// A [`Rectangle`] whose frame has A1 = cos γ E1 + sin γ E2, A2 = −sin γ E1 + cos γ E2,
/// A3 = E3 (γ the heading), starting at `start` (ground coordinates in units of R).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlacedRectangle {
    /// The rectangle in its own frame.
    pub rectangle: Rectangle,
    /// γ: angle from E1 to A1 about E3, radians.
    pub heading: f64,
    /// The start S on the ground, (E1, E2) components in units of R.
    pub start: [f64; 2],
}

impl PlacedRectangle {
    /// The rectangle in the ground frame itself: heading 0 (Aᵢ = Eᵢ), starting at the
    /// origin, as in Figure 2.3.
    #[must_use]
    pub fn at_origin(rectangle: Rectangle) -> Self {
        Self {
            rectangle,
            heading: 0.0,
            start: [0.0, 0.0],
        }
    }

    /// The frame rotation R(γ, E3), which maps Eᵢ to Aᵢ.
    #[must_use]
    pub fn frame(&self) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Vector3::z_axis(), self.heading)
    }

    /// The holonomy with components on {E1, E2, E3}: R(γ, E3) S R(γ, E3)ᵀ, where S has
    /// components on {A1, A2, A3} ((2.4.2), (2.4.5)).
    #[must_use]
    pub fn holonomy(&self) -> Rotation3<f64> {
        let f = self.frame();
        f * self.rectangle.holonomy() * f.transpose()
    }

    /// The corners of the centre's path on the ground, in the order of travel, units of R.
    #[must_use]
    pub fn waypoints(&self) -> Vec<[f64; 2]> {
        let (s, c) = self.heading.sin_cos();
        self.rectangle
            .waypoints()
            .into_iter()
            .map(|[x, y]| [self.start[0] + c * x - s * y, self.start[1] + s * x + c * y])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rectangle::Direction;

    #[test]
    fn at_origin_is_the_rectangle_itself() {
        let r = Rectangle::new(1.0, 0.5, 2.0, Direction::Cw).unwrap();
        let p = PlacedRectangle::at_origin(r);
        assert_eq!(p.waypoints(), r.waypoints());
        assert!(rotations::rotation_distance(&p.holonomy(), &r.holonomy()) < 1e-15);
    }
}
