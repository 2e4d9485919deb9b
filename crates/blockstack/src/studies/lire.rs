//! The outcome of a Leaning Tower of Lire run (§4.3, Figure 4.4): how many blocks fell
//! from the table, and how far the blocks drifted from their initial poses.

use crate::record::Frame;
use crate::scene::Scene;
use crate::simulation::BlockPose;

/// How many blocks lie fallen from the table: their lowest corner below the table's top
/// face (on the floor, or tilted down over the table's edge).
#[must_use]
pub fn blocks_fallen(scene: &Scene, poses: &[BlockPose]) -> usize {
    // Round-off margin on a height of order 1.
    let table_top = scene.base().top() - 1e-9;
    poses
        .iter()
        .zip(scene.blocks())
        .filter(|(p, b)| {
            let lowest = p.y
                - 0.5 * b.width() * p.theta.sin().abs()
                - 0.5 * b.height() * p.theta.cos().abs();
            lowest < table_top
        })
        .count()
}

/// The largest drift of any block coordinate (x, y, θ) of `frame` from the scene's
/// initial poses: how far an equilibrium has been left.
#[must_use]
pub fn largest_drift(scene: &Scene, frame: &Frame) -> f64 {
    frame
        .blocks
        .iter()
        .zip(scene.initial_coordinates().chunks_exact(3))
        .map(|(p, q)| {
            (p.x - q[0])
                .abs()
                .max((p.y - q[1]).abs())
                .max((p.theta - q[2]).abs())
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{lire, Perturbation};

    #[test]
    fn the_tower_at_rest_has_not_fallen_nor_drifted() {
        let scene = lire(4, Perturbation::None).unwrap();
        let q = scene.initial_coordinates();
        let frame = Frame::from_coordinates(&scene, &q, 0.0);
        assert_eq!(largest_drift(&scene, &frame), 0.0);
        let poses: Vec<BlockPose> = frame.blocks.iter().map(|&p| p.into()).collect();
        assert_eq!(blocks_fallen(&scene, &poses), 0);
        // The top block dropped by a block height below the table top has fallen.
        let mut low = poses.clone();
        low[3].y = scene.base().top() - 0.2;
        assert_eq!(blocks_fallen(&scene, &low), 1);
    }
}
