//! The directions a friction percussion is spanned by in the last resort's linear
//! complementarity problem (docs/last-resort.md).
//!
//! A planar law (one component) has the two directions ±1, and its LCP is Coulomb's law
//! exactly. A disk law (two components, ‖P_F‖ ≤ μ ΣP_N) is not polyhedral, so an LCP
//! takes it approximately (Stewart and Trinkle 1996): P_F = Σᵢ βᵢ dᵢ over k unit
//! directions dᵢ at angles 2πi/k, with 0 ≤ βᵢ ⟂ λ + dᵢᵀξ_F ≥ 0 and
//! 0 ≤ λ ⟂ μ ΣP_N − Σᵢ βᵢ ≥ 0. The friction disk becomes the regular k-gon inscribed in
//! it: the largest friction percussion lies between cos(π/k) μΣP_N (across an edge's
//! midpoint) and μΣP_N (at a vertex), depending on the direction of slip, and a
//! sliding contact's percussion points to the vertex or edge nearest to −ξ_F's
//! direction instead of exactly against it. Sticking is exact whenever the
//! sticking percussion lies inside the polygon.

/// The number k of directions of a disk friction law: the polygon's smallest radius is
/// cos(π/16) = 0.981 of the disk's ([`disk_bound_ratio`]), a friction bound at most 1.9 %
/// low. Each direction adds one unknown to the LCP per disk law (k + 1 in all with λ,
/// against 3 for a planar law).
pub const DISK_DIRECTIONS: usize = 16;

/// The smallest radius of the polygon relative to the disk's, cos(π/k): the worst-case
/// ratio of the last resort's friction bound to Coulomb's for a disk law.
#[must_use]
pub fn disk_bound_ratio() -> f64 {
    (std::f64::consts::PI / DISK_DIRECTIONS as f64).cos()
}

/// The directions of a law with `components` tangential components (1 or 2), each a
/// unit vector of that length: ±1 for a planar law (+1 first), the k-gon's vertices for
/// a disk law.
#[must_use]
pub(crate) fn directions(components: usize) -> Vec<Vec<f64>> {
    if components == 1 {
        return vec![vec![1.0], vec![-1.0]];
    }
    (0..DISK_DIRECTIONS)
        .map(|i| {
            let angle = 2.0 * std::f64::consts::PI * i as f64 / DISK_DIRECTIONS as f64;
            vec![angle.cos(), angle.sin()]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_polygon_is_inscribed_in_the_disk_with_the_stated_ratio() {
        let d = directions(2);
        assert_eq!(d.len(), DISK_DIRECTIONS);
        for v in &d {
            assert!((v[0].hypot(v[1]) - 1.0).abs() < 1e-15);
        }
        // The midpoint of an edge lies at cos(π/k) from the centre.
        let mid = [(d[0][0] + d[1][0]) / 2.0, (d[0][1] + d[1][1]) / 2.0];
        assert!((mid[0].hypot(mid[1]) - disk_bound_ratio()).abs() < 1e-15);
        assert!((disk_bound_ratio() - 0.981).abs() < 5e-4);
        assert_eq!(directions(1), vec![vec![1.0], vec![-1.0]]);
    }

    /// docs/method.md §8.2 and docs/last-resort.md state k and the bound's ratio as the
    /// program has them.
    #[test]
    fn the_docs_state_the_polygon_s_size_and_error() {
        let k = DISK_DIRECTIONS;
        for doc in [
            include_str!("../../../docs/method.md"),
            include_str!("../../../docs/last-resort.md"),
        ] {
            let doc = doc.replace('\n', " ");
            for stated in [
                format!("`nsga::friction_polygon::DISK_DIRECTIONS` = {k}"),
                format!("cos(π/{k}) = {:.3}", disk_bound_ratio()),
                format!("up to π/{k} off"),
            ] {
                assert!(doc.contains(&stated), "{stated}");
            }
        }
    }
}
