//! What the tour runs: for each system, the `rollstack` commands that reproduce its
//! headline results, each with what it shows and the thesis's numbers to compare with.
//! The tour adds `--out` for a step that writes files; everything else is what a user
//! would type.

use super::{SectionPlan, Step};

/// The rectangle Ŝ(4π/3 − 0.5, π/2 − 0.4, 3π, ccw) of (2.4.10), as flags.
macro_rules! rectangle_2_4_10 {
    () => {
        "--theta 3.6887902047863905 --phi1 1.1707963267948966 --phi2 3pi"
    };
}

/// The sections of the tour, in page order.
pub const SECTIONS: &[SectionPlan] = &[
    SectionPlan {
        name: "rotations",
        title: "Rotations: one rotation in every representation",
        steps: &[
            Step {
                args: "rotation --from axis-angle --values -0.389418,0,-0.921061,62.7042deg",
                out: "holonomy_2_4_10",
                text: "The holonomy (2.4.10) of the rolling sphere as printed (ψ = 62.7042°, \
                       s = −0.389418 A1 − 0.921061 A3) in every representation, with all twelve \
                       Euler sets (A.1.2); the CSV gives each set's round-trip error, the angle \
                       of R_targetᵀ R(a1, a2, a3). The picture shows the fixed basis E1, E2, E3 \
                       (grey), the rotated basis eᵢ = R Eᵢ (colour) and the axis (black).",
            },
            Step {
                args: "rotation --from axis-angle --values 0,0,1,0.9",
                out: "",
                text: "A rotation of 0.9 rad about E3 sits at the singular value of the \
                       symmetric sets (3-1-3, 3-2-3, …): the first angle is set to 0 and the \
                       third carries the whole rotation.",
            },
        ],
    },
    SectionPlan {
        name: "sphere",
        title: "Rolling sphere: holonomy and path planning (Ch. 2)",
        steps: &[
            Step {
                args: concat!("sphere holonomy ", rectangle_2_4_10!()),
                out: "holonomy_2_4_10",
                text: "The rectangle Ŝ(4π/3 − 0.5, π/2 − 0.4, 3π, ccw) of (2.4.10); the thesis \
                       prints ψ = 62.7042°, s = −0.389418 A1 − 0.921061 A3. The product (2.4.2), \
                       the corrected closed form (2.4.6) and the components (B.1.2) agree to \
                       round-off. psi_level_sets.png is Figure 2.5: the level sets of ψ(ϑ, φ2) \
                       from (2.4.11) with the factor 2 of ERRATA 1, the rectangle marked.",
            },
            Step {
                args: concat!("sphere roll ", rectangle_2_4_10!(), " --steps 600 --study"),
                out: "roll_2_4_10",
                text: "Figure 2.1: the same rectangle rolled with the exact integrator, the \
                       top view of the centre C and of the material point X that started at the \
                       contact, and the final orientation against the closed form. roll_study: \
                       error against wall time of the exact (Lie-group exponential) and RK4 \
                       integrators, 8 … 4096 steps.",
            },
            Step {
                args: "sphere plan --angle 3pi/2 --axis 0.1,0.9899494936611665,0.1",
                out: "plan_2_4_12",
                text: "(2.4.12), Figure 2.6: every rectangle with φ2 ∈ [0, 3π] that produces \
                       R(3π/2, 0.1 A1 + √0.98 A2 + 0.1 A3). The thesis prints the three \
                       counter-clockwise ones whose quaternion has q0 = cos(3π/4) (ERRATA 2, 7); \
                       the other sign of the quaternion and clockwise travel give the others.",
            },
            Step {
                args: "sphere euler-plan --set 3-2-3 --angles 0.6,1.1,1.4",
                out: "euler_3_2_3",
                text: "Figures 2.7–2.9: a rotation reached through its Euler angles as three \
                       rectangles, travelled cw, ccw, cw (ERRATA 6).",
            },
            Step {
                args: "sphere euler-plan --set 3-1-3 --angles 0.6,1.1,1.4",
                out: "euler_3_1_3",
                text: "",
            },
            Step {
                args: "sphere euler-plan --set 3-2-1 --angles 0.6,0.5,1.4",
                out: "euler_3_2_1",
                text: "",
            },
            Step {
                args: "sphere euler-plan --set 3-1-2 --angles 0.6,0.5,1.4",
                out: "euler_3_1_2",
                text: "",
            },
        ],
    },
    SectionPlan {
        name: "nsga",
        title: "Solver core: nonsmooth generalized-α (Capobianco et al. 2021)",
        steps: &[
            Step {
                args: "nsga ball --case 1",
                out: "",
                text: "The paper's rotating bouncing ball (m = 1, R = 0.1, μ = 0.2, Δt = 2e-3, \
                       ρ∞ = 0.5). Exact answers: first impact at 0.4284 s; case 2 rolls from \
                       0.728 s at ẋ = −1.4286; case 3 at −0.2857; case 4 at −0.7143.",
            },
            Step {
                args: "nsga ball --case 2",
                out: "ball_case_2",
                text: "",
            },
            Step {
                args: "nsga ball --case 3",
                out: "",
                text: "",
            },
            Step {
                args: "nsga ball --case 4",
                out: "",
                text: "",
            },
            Step {
                args: "nsga ball --case 2 --scheme moreau",
                out: "",
                text: "Moreau–Jean on case 2: the ball sinks into the ground at impacts.",
            },
            Step {
                args: "nsga work-precision --system oscillator --dts 8e-3,4e-3,2e-3,1e-3,5e-4 \
                       --rho-inf 0,0.5,1",
                out: "work_precision",
                text: "Phase-plane error at 1 s against wall time on the linear oscillator: \
                       second order for every ρ∞ and for Moreau–Jean.",
            },
        ],
    },
    SectionPlan {
        name: "cylinder",
        title: "Inclined rolling cylinders (Ch. 3, App. D–F)",
        steps: &[
            Step {
                args: "cylinder support --theta 30deg --r-over-h 0.1 --mu 0.2",
                out: "",
                text: "Steady support (§3.3, corrected per ERRATA 9–11) at the parameters of \
                       Figures 3.3, 3.7 and 3.8: the normal force at the two friction limits \
                       (3.3.8) and on a smooth plane (3.3.10), and the smallest applied force \
                       (3.3.15)–(3.3.19), checked against a numerical (QR) solution of the \
                       balance laws (3.3.3).",
            },
            Step {
                args: "cylinder statics",
                out: "statics",
                text: "Figures 3.3 (feasible normal force between the friction limits), 3.4 \
                       (r/h = 0, 0.05, 0.1, 0.15; the + curves meet at (3.3.11)), 3.5 (μ = 0 … \
                       0.6), 3.7 (the unconstrained minimum traces the circle on BC, (3.3.20)) \
                       and 3.8 (the least applied force, zero at D = arctan(2r/h)).",
            },
            Step {
                args: "cylinder holonomy rectangle --theta pi/10 --phi1 13pi/3 --phi2 29pi/4 \
                       --r-over-h 0.12 --case I --max-step 2e-3",
                out: "fig3_10_case_I",
                text: "Figure 3.10 (h = 8.3333 r, ϑ = π/10): the contact point traces a \
                       rectangle; Δφ = ±139π/12 = ±36.3901 rad in radians (ERRATA 8), from the \
                       product of nine rotations (3.4.3) and by rolling.",
            },
            Step {
                args: "cylinder holonomy rectangle --theta pi/10 --phi1 13pi/3 --phi2 29pi/4 \
                       --r-over-h 0.12 --case II --max-step 2e-3",
                out: "fig3_10_case_II",
                text: "",
            },
            Step {
                args: "cylinder holonomy circle --ell 9.442390112871163 --theta pi/10 \
                       --r-over-h 0.075 --case I --max-step 2e-3",
                out: "fig3_12_case_I",
                text: "Figure 3.12 (h = 13.3333 r, ϑ = π/10, k = 25/3 r): the contact point \
                       traces a circle of radius ℓ = 9.44239 r (the printed 9.44233 is a \
                       rounding slip, ERRATA 8); Δφ = ±59.3283 rad.",
            },
            Step {
                args: "cylinder holonomy circle --ell 9.442390112871163 --theta pi/10 \
                       --r-over-h 0.075 --case II --max-step 2e-3",
                out: "fig3_12_case_II",
                text: "",
            },
            Step {
                args: "cylinder frobenius --system single",
                out: "",
                text: "Frobenius test (App. D, F) with exact derivatives and an SVD null \
                       space. One cylinder: only Π3 is integrable (D.2.4).",
            },
            Step {
                args: "cylinder frobenius --system pair9 --config touching",
                out: "",
                text: "The pair: the nine rolling constraints have rank 9, not the 8 of (F.2.5) \
                       (ERRATA 13); with seven, the normal constraint Π7 is the rate of the gap \
                       and so integrable.",
            },
            Step {
                args: "cylinder frobenius --system pair7 --config touching",
                out: "",
                text: "",
            },
        ],
    },
    SectionPlan {
        name: "blocks",
        title: "Block stack (Ch. 4, App. I)",
        steps: &[
            Step {
                args: "blocks lire",
                out: "lire_none",
                text: "The Leaning Tower of Lire (§4.3): four blocks w = 1 in the harmonic \
                       maximum-overhang configuration, offsets w/8, w/6, w/4, w/2 (25/24 w in \
                       all; (4.3.1) as printed gives w/2, ERRATA 16). Unperturbed, it is an \
                       equilibrium: the snapshot at t = 0 is Figure 4.3.",
            },
            Step {
                args: "blocks lire --perturb top",
                out: "",
                text: "The top block shifted outward by 1 % of w: it topples alone.",
            },
            Step {
                args: "blocks lire --perturb bottom",
                out: "lire_bottom",
                text: "Figure 4.4: the lowest block shifted outward by 1 % of w makes the tower \
                       collapse (snapshots at t = 0, 5, 6.4). As in the thesis, nothing lies \
                       below the table and the blocks fall freely.",
            },
            Step {
                args: "blocks lire --perturb bottom --floor",
                out: "lire_floor",
                text: "The same collapse on a floor at the bottom of the table (beyond the \
                       thesis): the blocks land.",
            },
            Step {
                args: "blocks lire --perturb bottom --prox-constant 0.3",
                out: "",
                text: "The collapse with the thesis's constant prox parameter r = 0.3 (§4.2) \
                       instead of the scaled one: compare the failed Newton steps.",
            },
            Step {
                args: "blocks shake --blocks 4 --omega 4",
                out: "shaking",
                text: "A column of four blocks w = 0.2, h = 0.4 on a base shaken as \
                       x = 0.2 sin(4t) (§4.4): the failure time, and the angle and height of the \
                       top block (cf. Figure 4.5 (b), (c)). After the failure the picture is \
                       not physical yet: the model has contacts only between neighbours in the \
                       stack and with the floor, so a fallen block can pass through the base or \
                       another block.",
            },
            Step {
                args: "blocks shake --blocks 4 --omega 4 --prox-constant 0.3",
                out: "",
                text: "The shaken column with the thesis's constant prox parameter r = 0.3.",
            },
            Step {
                args: "blocks sweep slide --v0 0.05,0.1,0.5,1,2,5,10",
                out: "slide",
                text: "Figure 4.7 (few points): the top block's angle at t = 3 against the \
                       speed of the pulled base; small v0 rides along, intermediate v0 topples, \
                       large v0 drops almost straight (the tablecloth trick).",
            },
            Step {
                args: "blocks work-precision --system block",
                out: "work_precision",
                text: "Speed against error for a block stack: one block sliding and rocking \
                       on a shaken base, the error at t = 2 against a run with Δt/16, NSGA \
                       beside Moreau–Jean, with the observed orders of convergence \
                       (`--system column` and `--system lire` for the other scenes).",
            },
            Step {
                args: "blocks painleve --aspect 0.5 --mu 0.2",
                out: "painleve",
                text: "Painlevé's paradoxes for one block (App. I, Figure I.2, ERRATA 18): the \
                       least μ_d = 4/3, the admissible angles (I.1.3), where b ≤ 0 per slip \
                       direction, and the line-contact forces (I.2.10).",
            },
        ],
    },
];
