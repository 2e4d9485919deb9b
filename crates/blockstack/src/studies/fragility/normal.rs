//! The standard normal distribution: its density φ, its distribution function Φ and
//! their logarithms, to double precision in both tails (the fit of a fragility curve
//! takes ln Φ of arguments far out in a tail while it searches).
//!
//! Φ is Hart's algorithm 5666 as West (2005, "Better approximations to cumulative normal
//! functions", Wilmott Magazine) writes it: a rational function of |z| times e^(−z²/2)
//! for |z| < 5√2, Laplace's continued fraction beyond, accurate to 1e-13 relative in
//! the lower tail, so that ln Φ(z) stays accurate where Φ(z) is tiny.

/// √(2π).
const SQRT_2PI: f64 = 2.506_628_274_631_000_5;

/// Beyond this |z| the lower tail Φ(−|z|) underflows to 0 (below 1e-300).
const TAIL: f64 = 37.0;

/// The density φ(z) = e^(−z²/2)/√(2π).
#[must_use]
pub fn pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / SQRT_2PI
}

/// The lower tail Φ(−|z|), accurate relative to itself.
fn lower_tail(z: f64) -> f64 {
    let x = z.abs();
    if x > TAIL {
        return 0.0;
    }
    let e = (-0.5 * x * x).exp();
    if x < 7.071_067_811_865_47 {
        let num = [
            3.526_249_659_989_109e-2,
            0.700_383_064_443_688_1,
            6.373_962_203_531_65,
            33.912_866_078_383,
            112.079_291_497_870_9,
            221.213_596_169_931_1,
            220.206_867_912_376_1,
        ];
        let den = [
            8.838_834_764_831_844e-2,
            1.755_667_163_182_642,
            16.064_177_579_206_95,
            86.780_732_202_946_08,
            296.564_248_779_673_7,
            637.333_633_378_831_1,
            793.826_512_519_948_4,
            440.413_735_824_752_2,
        ];
        let horner = |c: &[f64]| c.iter().fold(0.0, |acc, &k| acc * x + k);
        e * horner(&num) / horner(&den)
    } else {
        // Laplace's continued fraction x + 1/(x + 2/(x + 3/(x + …))), to 40 terms:
        // West's five terms leave 1e-8 at x = 8, forty converge to round-off.
        let b = (1..=40).rev().fold(x, |b, k| x + f64::from(k) / b);
        e / b / SQRT_2PI
    }
}

/// Φ(z), the probability that a standard normal variable is below z.
#[must_use]
pub fn cdf(z: f64) -> f64 {
    if z <= 0.0 {
        lower_tail(z)
    } else {
        1.0 - lower_tail(z)
    }
}

/// ln Φ(z), finite for every finite z: beyond the underflow of Φ, the first term of its
/// asymptotic series, ln φ(z) − ln(−z).
#[must_use]
pub fn ln_cdf(z: f64) -> f64 {
    if z < -TAIL {
        -0.5 * z * z - (-z).ln() - SQRT_2PI.ln()
    } else if z <= 0.0 {
        lower_tail(z).ln()
    } else {
        (-lower_tail(z)).ln_1p()
    }
}

/// The inverse Mills ratio λ(z) = φ(z)/Φ(z): the derivative of ln Φ(z). Beyond the
/// underflow of Φ, its asymptote −z/(1 − 1/z²).
#[must_use]
pub fn mills(z: f64) -> f64 {
    if z < -TAIL {
        -z / (1.0 - 1.0 / (z * z))
    } else {
        pdf(z) / cdf(z)
    }
}

/// The z with Φ(z) = p, by Newton's method on Φ from a logistic start (for the band's
/// quantile and the tests; p in (0, 1)).
#[must_use]
pub fn quantile(p: f64) -> f64 {
    let mut z = (p / (1.0 - p)).ln() / 1.702;
    for _ in 0..60 {
        let step = (cdf(z) - p) / pdf(z).max(f64::MIN_POSITIVE);
        z -= step.clamp(-1.0, 1.0);
        if step.abs() < 1e-15 * z.abs().max(1.0) {
            break;
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phi_matches_reference_values_in_both_tails() {
        // Values of 0.5·erfc(−z/√2) to 16 digits (mpmath.ncdf).
        let reference = [
            (-40.0, 0.0),
            (-8.0, 6.220_960_574_271_784e-16),
            (-3.0, 1.349_898_031_630_094_5e-3),
            (-1.0, 0.158_655_253_931_457_05),
            (0.0, 0.5),
            (1.0, 0.841_344_746_068_542_9),
            (2.5, 0.993_790_334_674_224),
        ];
        for (z, p) in reference {
            let got = cdf(z);
            assert!(
                (got - p).abs() <= 1e-13 * p.max(1e-300),
                "Φ({z}) = {got}, expected {p}"
            );
        }
        assert!((ln_cdf(-8.0) - 6.220_960_574_271_784e-16_f64.ln()).abs() < 1e-13);
        assert!(ln_cdf(-50.0).is_finite() && ln_cdf(-50.0) < -1200.0);
        assert!((ln_cdf(9.0)).abs() < 1e-18 && ln_cdf(9.0) < 0.0);
        // The asymptote of λ takes over from φ/Φ without a jump.
        assert!((mills(-36.999) / mills(-37.001) - 1.0).abs() < 1e-4);
        for p in [1e-6, 0.025, 0.5, 0.975] {
            assert!((cdf(quantile(p)) - p).abs() < 1e-15, "{p}");
        }
        assert!((quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-12);
    }
}
