//! Generalized-α parameters from the spectral radius at infinity ρ∞ (paper eq. 72).

/// α_m, α_f, γ, β of the generalized-α scheme for one ρ∞ (paper eq. 72).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GenAlpha {
    /// Spectral radius at infinity ρ∞ ∈ [0, 1].
    pub rho_inf: f64,
    /// α_m = (2ρ∞ − 1)/(ρ∞ + 1).
    pub alpha_m: f64,
    /// α_f = ρ∞/(ρ∞ + 1).
    pub alpha_f: f64,
    /// γ = ½ + α_f − α_m.
    pub gamma: f64,
    /// β = ¼(½ + γ)².
    pub beta: f64,
}

impl GenAlpha {
    /// The parameters of eq. (72). `rho_inf` is clamped to [0, 1]; NaN gives 0.5.
    #[must_use]
    pub fn new(rho_inf: f64) -> Self {
        let r = if rho_inf.is_nan() {
            0.5
        } else {
            rho_inf.clamp(0.0, 1.0)
        };
        let alpha_m = (2.0 * r - 1.0) / (r + 1.0);
        let alpha_f = r / (r + 1.0);
        let gamma = 0.5 + alpha_f - alpha_m;
        let beta = 0.25 * (0.5 + gamma) * (0.5 + gamma);
        Self {
            rho_inf: r,
            alpha_m,
            alpha_f,
            gamma,
            beta,
        }
    }

    /// α_r = (1 − α_f)/(1 − α_m) = ∂ā_{n+1}/∂a_{n+1} (eq. 71).
    #[must_use]
    pub fn alpha_r(&self) -> f64 {
        (1.0 - self.alpha_f) / (1.0 - self.alpha_m)
    }

    /// The auxiliary variable update ā_{n+1} = (α_f a_n + (1 − α_f) a − α_m ā_n)/(1 − α_m)
    /// (eq. 71); also used for λ̄_N and λ̄_F (eqs. 96, 114).
    #[must_use]
    pub fn bar(&self, old: f64, new: f64, old_bar: f64) -> f64 {
        (self.alpha_f * old + (1.0 - self.alpha_f) * new - self.alpha_m * old_bar)
            / (1.0 - self.alpha_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn rho_half_matches_spec() {
        let p = GenAlpha::new(0.5);
        assert_relative_eq!(p.alpha_m, 0.0, epsilon = 1e-15);
        assert_relative_eq!(p.alpha_f, 1.0 / 3.0, epsilon = 1e-15);
        assert_relative_eq!(p.gamma, 5.0 / 6.0, epsilon = 1e-15);
        assert_relative_eq!(p.beta, 4.0 / 9.0, epsilon = 1e-15);
    }

    proptest::proptest! {
        #[test]
        fn second_order_condition(r in 0.0..=1.0f64) {
            // γ = ½ + α_f − α_m is the second-order condition; α_r > 0 keeps ā defined.
            let p = GenAlpha::new(r);
            proptest::prop_assert!((p.gamma - (0.5 + p.alpha_f - p.alpha_m)).abs() < 1e-14);
            proptest::prop_assert!(p.alpha_r() > 0.0 && p.alpha_m < 1.0);
        }
    }
}
