"""Every checkable claim of the paper, with its place and the paper's words.

The paper is the LaTeX source in shared/seed/ (main text, captions and the
supplement).  `CLAIMS` is the one list the reproduction report
(python/slipstrip/report/, docs/reproduction.md) walks: each entry becomes a
row with a verdict under each material reading, and a test
(tests/python/test_report.py) checks that the report's table holds every id,
so none is dropped.  `MEASUREMENTS` are numbers the report shows that the
paper does not claim (e.g. where the large-event peak of p(T) lies relative to
the 2H/c_s arrows); they are listed apart and not counted.

`words` quotes the paper (LaTeX turned into plain text, ellipses mark cuts);
`value` is the number or statement a verdict compares with; `height` is the
strip height the paper states an Lc number at; `group` joins
claims that are one computation (every Lc number is one linear-stability
computation with the reading's material), so that the reading conclusion
counts them once.
"""
from __future__ import annotations

import dataclasses


@dataclasses.dataclass(frozen=True)
class Claim:
    id: str
    section: str
    claim: str        # what the row tests, in one line
    where: str        # place in the paper
    words: str        # the paper's words
    value: object = None   # number or short statement the verdict uses
    group: str = ""        # claims that are one computation (the Lc numbers) share a group
    height: float | None = None  # [m] the strip height H the paper states the claim at (the Lc numbers)

    # The report and its older callers read these two names.
    @property
    def text(self) -> str:
        return self.words


S_FIG1 = "Fig. 1: statistics of the reference case"
S_FIG2 = "Fig. 2: event hierarchy (H = 0.1 m, L = 2 m)"
S_FIG3AB = "Fig. 3a/3b: controlled nucleation"
S_FIG3CD = "Figs. 3c/3d and S7: the wave-reflection time 2H/c_s in the statistics"
S_ROBUST = "Figs. 4, S10-S12: robustness of complexity"
S_FIG5 = "Fig. 5: reverse transition, and the friction curves"
S_LC = "Lc(H), mesh and process zone"
S_PROC = "Event identification, stationarity, threshold, clusters (Figs. S4-S9)"

C = Claim
CLAIMS: tuple[Claim, ...] = (
    # ---------------------------------------------------------------- Fig. 1
    C("fig1b_space_slip", S_FIG1, "space-slip map v(x, δ)/v0 shows rapid-slip patches and sticking lines",
      "Fig. 1b; main text 'Statistical complexity'",
      "dark blue/green patches in the space-slip plot correspond to slip occurring roughly at the same time. "
      "On the other hand, the bright/white end of the color code essentially corresponds to a sticking state, "
      "v(x,δ)/v0 << 1, hence the bright white lines indicate non-sliding interfacial patches"),
    C("fig1c_exp_u", S_FIG1, "small-event (u < D) power law of p(u/D), exponent ~ -2.45", "Fig. 1c caption",
      "The dashed line, added as a guide to the eye, corresponds to a power-law with an exponent of ≃ -2.45", 2.45),
    C("fig1d_exp_T", S_FIG1, "small-event power law of p(T v0/D), exponent ~ -2.2", "Fig. 1d caption",
      "The dashed line corresponds to a power-law with an exponent of ≃ -2.2", 2.2),
    C("fig1e_exp_M0", S_FIG1, "small-event power law of p(M0/(mu D L)), exponent ~ -2", "Fig. 1e caption",
      "The dashed line corresponds to a power-law with an exponent of ≃ -2", 2.0),
    C("fig1c_split_at_D", S_FIG1, "p(u) changes from the power law to the hump near u = D",
      "main text 'Statistical complexity' (Fig. 1c)",
      "the two parts of p(ū) appear to be approximately distinguished by being smaller or larger than ū = D "
      "(marked by the vertical solid line in Fig. 1c)", 1.0),
    C("fig1d_lognormal_T", S_FIG1, "large events (u ≥ D): T log-normal", "Fig. 1d inset; main text",
      "The latter are predominantly parabolic (recall the double-logarithmic scale used) and hence indicate a "
      "log-normal distribution, as demonstrated in the corresponding insets", "log-normal"),
    C("fig1e_lognormal_M0", S_FIG1, "large events (u ≥ D): M0 log-normal", "Fig. 1e (inset as in 1d); main text",
      "we ... superpose the p(T) and p(M0) distributions for the remaining slip events in Fig. 1d-e ... The latter "
      "are predominantly parabolic ... and hence indicate a log-normal distribution", "log-normal"),
    C("small_nonpropagating", S_FIG1, "small events (u < D) have L_s/T > c_d; large ones are propagating",
      "main text 'Statistical complexity'",
      "L_s/T that is associated with slip events with ū < D attains values that are significantly larger than "
      "the dilatational wave-speed c_d (not shown) ... The complementary regime, ū > D, approximately "
      "corresponds to larger, propagating slip events", "L_s/T > c_d"),
    C("small_slip_fraction", S_FIG1, "small events carry 8 % of the total slip", "main text, discussion of Fig. 2",
      "all of the small events in this simulation, i.e., those featuring ū < D in Fig. 1c, accounted for 8% of "
      "the total slip accommodated by the interface over the entire simulation", 0.08),
    C("reference_complex", S_FIG1, "H = 0.1 m, L = 4 m: a stochastic, statistically stationary (complex) state",
      "main text 'Results'; Summary",
      "After a finite time transient, the system settles into a stochastic, statistically-stationary state",
      "complex"),
    # ---------------------------------------------------------------- Fig. 2
    C("fig2_event1_bilateral", S_FIG2, "large arrested events (event 1) grow bilaterally from their nucleation site",
      "main text on Fig. 2a", "nucleated at x/L ≃ 0.35, and propagated bi-laterally until being arrested"),
    C("fig2_event1_vmax", S_FIG2, "event 1: largest slip rate more than 10 v0", "main text on Fig. 2a",
      "accompanied by a maximal slip velocity of more than an order of magnitude larger than the applied one", 10.0),
    C("fig2_event1_duration", S_FIG2, "event 1: duration comparable to 2H/c_s", "main text on Fig. 2",
      "the duration of event 1 is comparable with the back-and-forth elastic shear waves travel time 2H/c_s", 1.0),
    C("fig2_event1_crack", S_FIG2, "event 1: crack-like slip profile sqrt((L_s/2 - Δx)(L_s/2 + Δx))",
      "main text on Fig. 2b",
      "The slip accumulated by event 1 is approximately proportional to the functional form "
      "sqrt((L_s/2-Δx)(L_s/2+Δx)) ... a clear signature of conventional crack-like scaling"),
    C("fig2_event1_arrest_minima", S_FIG2, "event 1 arrests at local minima of the pre-event stress",
      "main text on Fig. 2d",
      "The arrest locations appear to coincide with local minima of the stress field τ(x)/σ0 (black curve in "
      "Fig. 2d) into which event 1 propagated, possibly indicating a causal relation between the two"),
    C("fig2_event1_aging", S_FIG2, "outside the slip zone of event 1 the contact ages (φ increases)",
      "main text on Fig. 2c",
      "Outside the slipping domain of extent L_s, the interface has experienced contact aging under nearly stick "
      "conditions (increase in the contact time φ)"),
    C("fig2_event1_stress_peaks", S_FIG2, "stress maxima at the arrest edges of event 1 after it",
      "main text on Fig. 2d",
      "as expected from a crack-like object, the arrested event 1 gave rise to significant stress concentration "
      "near the arrest locations (see local maxima of the green curve in Fig. 2d at the vertical black lines)"),
    C("fig2_events23_crack", S_FIG2, "small events (events 2-3): non-propagating, slip < D, crack-like of fixed extent",
      "main text on Fig. 2b insets",
      "events 2 and 3 are non-propagating and accommodate slip less than D ... their slip also approximately "
      "follows a crack-like scaling ... indicating that they are in fact crack-like objects of an approximately "
      "fixed spatial extent L_s"),
    C("fig2_event4_from_arrest", S_FIG2, "large events nucleate at the arrest sites of earlier events (event 4)",
      "main text on Fig. 2a inset",
      "Event 4 did involve propagation away from the arrest location of event 1 at x/L ≃ 0.2 ... their nucleation "
      "seems to be influenced by large stress gradients accompanying static stress concentrations left by "
      "previous events"),
    C("fig2_event5_bilateral_stage", S_FIG2, "event 5: bilateral stage lasting ~2H/c_s", "main text on Fig. 2a",
      "The duration of the bi-lateral propagation stage, roughly corresponding to the vertical width of the red "
      "patch at the center of event 5, is comparable to 2H/c_s", 1.0),
    C("fig2_event5_pulses", S_FIG2, "event 5: then two pulses of size ~H", "main text on Fig. 2a",
      "This rupture event propagated bi-laterally for a certain amount of time until it transformed into two "
      "propagating slip pulses of size comparable to H", 1.0),
    # ---------------------------------------------------------------- Fig. 3a/b
    C("fig3a_duration", S_FIG3AB, "H = 0.1 m: the nucleated event lasts ~2H/c_s, then arrests",
      "Fig. 3a caption and text",
      "The duration of the slip event, from the time the slip velocity becomes sizable until arrest is comparable "
      "to the wave reflection time 2H/c_s", 1.0),
    C("fig3b_center_stop", S_FIG3AB, "H = 0.2 m: slip at the middle stops after ~2H/c_s", "main text on Fig. 3b",
      "slip at the middle of the event stops after a time interval comparable to the wave reflection time 2H/c_s",
      1.0),
    C("fig3b_pulses", S_FIG3AB, "H = 0.2 m: two pulses propagate and traverse the interface", "main text on Fig. 3b",
      "this time two pulses subsequently propagate across the system ... they traverse the entire interface", 2),
    C("fig3b_speed", S_FIG3AB, "H = 0.2 m: pulses supershear, close to c_d", "main text on Fig. 3b",
      "The pulses are supershear, i.e., propagate at a velocity close to the dilatational wave-speed c_d", 1.0),
    C("fig3b_width", S_FIG3AB, "H = 0.2 m: pulse size ~H", "main text and caption of Fig. 3b",
      "and feature a characteristic size H (as indicated by the horizontal white bar ...)", 1.0),
    # ---------------------------------------------------------------- Fig. 3c/d, S7
    C("fig3c_shift", S_FIG3CD, "large-event peak of p(T) moves to larger T with H (0.05, 0.1, 0.2 m)",
      "main text on Fig. 3c",
      "the peak of the large, propagating slip events part of p(T) is systematically shifted to higher values "
      "with increasing H", "increasing"),
    C("fig3d_shift", S_FIG3CD, "large-event peak of p(T) moves to larger T as c_s decreases (rho = 300, 1200, 4800)",
      "main text on Fig. 3d",
      "reducing the elastic wave-speeds has a similar dynamical effect on the statistics as increasing H",
      "increasing"),
    C("fig3_collapse", S_FIG3CD, "halving/doubling H ~ doubling/halving c_s on the large-event p(T)",
      "main text on Fig. 3d",
      "doubling/halving c_s has a similar (though not strictly identical) effect on the large, propagating slip "
      "events part of p(T) as that of halving/doubling H, respectively", "similar"),
    C("fig3_small", S_FIG3CD, "small-event p(T) weakly dependent on H and c_s", "Summary and Discussion (Fig. 3c-d)",
      "the statistics of the small slip event are weakly dependent on H and c_s (Fig. 3c-d)", "weak"),
    C("s7_shift_H", S_FIG3CD, "large-event peak of p(u) moves to larger u with H", "Fig. S7a, Sect. 'Wave reflection'",
      "The peak in the distribution of large events is shifted to the right when increasing the timescale 2H/c_s "
      "in both cases", "increasing"),
    C("s7_shift_cs", S_FIG3CD, "large-event peak of p(u) moves to larger u as c_s decreases",
      "Fig. S7b, Sect. 'Wave reflection'",
      "The peak in the distribution of large events is shifted to the right when increasing the timescale 2H/c_s "
      "in both cases", "increasing"),
    # ---------------------------------------------------------------- robustness
    C("fig4_complex", S_ROBUST, "slip law (Fig. 4): complexity retained", "main text on Fig. 4",
      "the statistical distributions in Fig. 4b-d are qualitatively --- and even semi-quantitatively (see figure "
      "caption) --- similar to their aging law counterparts", "complex"),
    C("fig4_exponents", S_ROBUST, "slip law: small-event power laws with the Fig. 1 exponents", "Fig. 4 caption",
      "The superimposed dashed lines in panels (b), (c) and (d) correspond to power-laws with the same exponents "
      "as in Fig. 1c-e"),
    C("fig4_lognormal_T", S_ROBUST, "slip law: large-event T log-normal (inset of Fig. 4c)", "Fig. 4c caption",
      "The inset presents a log-normal fit (solid yellow line) to the latter", "log-normal"),
    C("fig4_larger", S_ROBUST, "slip law: events span a larger part of the interface", "Fig. 4 caption (a)",
      "The plot reveals slip events that span a larger portion of the interface compared to those observed in "
      "Fig. 1b", "larger"),
    C("fig4_Lc_same", S_ROBUST, "slip law leaves Lc(H) unchanged", "main text on Figs. 4-5",
      "Replacing the aging evolution law by the slip evolution law (without changing the frictional parameters), "
      "as done in Fig. 4, leaves Lc(H) unchanged"),
    C("s10_complex", S_ROBUST, "D / 3 (Fig. S10): complexity retained", "Sect. 'Robustness'",
      "Both figures further demonstrate that the emergence of complexity is not affected by these variations",
      "complex"),
    C("s10_exponents", S_ROBUST, "D / 3: small-event power laws with the Fig. 1 exponents", "Fig. S10 caption",
      "The superimposed dashed lines ... correspond to power-laws with the same exponents as in Fig. 1c-e to "
      "highlight the quantitative similarity"),
    C("s10_lognormal_T", S_ROBUST, "D / 3: large-event T log-normal (inset of Fig. S10c)", "Fig. S10 caption",
      "The inset presents a log-normal fit (solid yellow line) to the latter", "log-normal"),
    C("s10_Lc_smaller", S_ROBUST, "D / 3 decreases Lc(H)", "Fig. S10 caption",
      "Decreasing D results in a smaller critical nucleation length Lc"),
    C("s10_min_propagating", S_ROBUST, "D / 3: smaller minimal size of propagating events", "Fig. S10 caption",
      "and consequently leads to a smaller minimal size for propagating events"),
    C("s11_complex", S_ROBUST, "a / 3 (Fig. S11): complexity retained", "Sect. 'Robustness'",
      "Both figures further demonstrate that the emergence of complexity is not affected by these variations",
      "complex"),
    C("s11_exponents", S_ROBUST, "a / 3: small-event power laws with the Fig. 1 exponents", "Fig. S11 caption",
      "The superimposed dashed lines ... correspond to power-laws with the same exponents as in Fig. 1c-e"),
    C("s11_lognormal_T", S_ROBUST, "a / 3: large-event T log-normal (inset of Fig. S11c)", "Fig. S11 caption",
      "The inset presents a log-normal fit (solid yellow line) to the latter", "log-normal"),
    C("s11_Lc_smaller", S_ROBUST, "a / 3 decreases Lc(H)", "Fig. S11 caption",
      "Decreasing a results in stronger rate-weakening behavior at intermediate velocities and in a smaller "
      "critical nucleation length Lc"),
    C("s12_complex", S_ROBUST, "f0 = 0.313, a = 0.00166, b = 0.067 (Fig. S12): complexity retained",
      "Sect. 'Robustness'",
      "Both figures further demonstrate that the emergence of complexity is not affected by these variations",
      "complex"),
    C("s12_exponents", S_ROBUST, "Fig. S12 friction: small-event power laws with the Fig. 1 exponents",
      "Fig. S12 caption",
      "The superimposed dashed lines ... correspond to power-laws with the same exponents as in Fig. 1c-e"),
    C("s12_lognormal_T", S_ROBUST, "Fig. S12 friction: large-event T log-normal (inset of Fig. S12c)",
      "Fig. S12 caption", "The inset presents a log-normal fit (solid yellow line) to the latter", "log-normal"),
    C("s12_Lc_smaller", S_ROBUST, "Fig. S12 friction decreases Lc(H)", "Fig. S12 caption",
      "Stronger rate-weakening behavior implies a smaller critical nucleation length Lc"),
    C("s12_fss", S_ROBUST, "Fig. S12 friction keeps f_ss(v0) and steepens the rate weakening", "Fig. S12 caption",
      "their coordinated effect is to maintain f_ss(v0) at its reference value (recall that v0 is the driving "
      "velocity), but to increase the magnitude of rate-weakening"),
    # ---------------------------------------------------------------- Fig. 5
    C("fig5_pulse", S_FIG5, "Fig. 5 friction (H = 0.1 m): periodic travelling pulse", "Fig. 5 caption",
      "the system settles, after a short coarsening transient, into a spatially periodic traveling pulse solution "
      "(that persistently propagates through the periodic boundary conditions)", "pulse"),
    C("fig5_H02", S_FIG5, "Fig. 5 friction at H = 0.2 m: no complexity", "main text, discussion of Fig. 5",
      "We also performed simulations with the friction law of Fig. 5, but with H = 0.2 m (i.e., doubling H) and "
      "did not observe complexity (not shown)", "no complexity"),
    C("reference_no_pulse", S_FIG5, "reference case: the periodic solution is avoided", "Abstract; Summary",
      "coarsening is less effective and the periodic solution is dynamically avoided", "no pulse"),
    C("fss_slopes", S_FIG5, "df_ss(v0)/d log v = -0.016 (Table S1) and -0.00588 (Fig. 5)", "Fig. 5 caption",
      "the logarithmic rate-weakening was reduced from df_ss(v0)/dlog(v) = -0.016 ... and df_ss(v0)/dlog(v) = "
      "-0.00588, i.e., by nearly a factor of 3", (-0.016, -0.00588)),
    C("fig5_fss", S_FIG5, "Fig. 5 friction keeps f_ss(v0) at its reference value", "Fig. 5 caption",
      "The latter are chosen such that their coordinated effect is to maintain f_ss(v0) = τ[v0, φ_ss(v0)]/σ0 at "
      "its reference value"),
    # ---------------------------------------------------------------- Lc(H)
    C("Lc_01", S_LC, "Lc(H = 0.1 m), Table S1 friction", "main text (Fig. 5 discussion); Fig. S2",
      "for the reference parameters of Table S1 ... (with H = 0.1 m ...) one has Lc(H) ≃ 0.35 m", 0.35, group="Lc", height=0.1),
    C("Lc_over_H_01", S_LC, "Lc/H at H = 0.1 m", "main text (Fig. 5 discussion)",
      "This corresponds to Lc(H)/H ≃ 3.5", 3.5, group="Lc", height=0.1),
    C("Lc_ratio_005", S_LC, "Lc(H = 0.05 m) / Lc(inf)", "supplement, Sect. 'Lc(H)'",
      "Lc varies from ≈ 65% of Lc(H → ∞) (with H = 0.05 m)", 0.65, group="Lc", height=0.05),
    C("Lc_ratio_01", S_LC, "Lc(H = 0.1 m) / Lc(inf)", "supplement, Sect. 'Lc(H)'",
      "with H = 0.1 m, the critical nucleation length corresponds to ≈ 80% of Lc(H → ∞)", 0.80, group="Lc", height=0.1),
    C("Lc_ratio_02", S_LC, "Lc(H = 0.2 m) / Lc(inf)", "supplement, Sect. 'Lc(H)'",
      "to almost ≈ 100% of Lc(H → ∞) (with H = 0.2 m)", 1.00, group="Lc", height=0.2),
    C("Lc5_01", S_LC, "Lc(H = 0.1 m), Fig. 5 friction", "main text (Fig. 5 discussion)",
      "the smaller |df_ss(v0)/dlog(v)| in Fig. 5 corresponds to Lc(H) ≃ 0.7 m, leading to Lc(H)/H ≃ 7", 0.7, group="Lc", height=0.1),
    C("Lc5_02", S_LC, "Lc(H = 0.2 m), Fig. 5 friction", "main text (Fig. 5 discussion)",
      "In this case, we found Lc(H) ≃ 0.9 m, leading to Lc(H)/H ≃ 4.5", 0.9, group="Lc", height=0.2),
    C("Lc_over_dx", S_LC, "Lc/Δx = O(100) at Δx = 2.5 mm", "supplement, Sect. 'Mesh discretization'",
      "we set Δx = 2.5×10^-3 m such that the nucleation length is discretized with Lc/Δx = O(100) elements", 100.0, group="Lc"),
    C("pz_formula", S_LC, "process zone estimate μD/(bσ0(1-ν)) = 9.5×10^-2 m", "supplement, Sect. 'Mesh discretization'",
      "The process zone size can be estimated as Δpz = O(μD/b σ0 [1-ν]) = 9.5×10^-2 m", 0.095),
    C("pz_resolved", S_LC, "process zone resolved by ~40 elements (tip zone measured in Fig. 3a/3b)",
      "supplement, Sect. 'Mesh discretization'", "implying that is it resolved by ~40 elements", 40.0),
    # ---------------------------------------------------------------- procedure
    C("ns_and_events", S_PROC, "O(10^7) nodal slips and O(10^4) events in a run (H = 0.2 m example)",
      "supplement, Sect. 'Identification of slip events' (Fig. S4)",
      "in the entire simulation shown in Fig. S4a, there are O(10^7) NSs ... There are O(10^4) slip events after "
      "applying this procedure", (1e7, 1e4)),
    C("first_event_spans", S_PROC, "the first event of every run spans the interface",
      "supplement, Sect. 'Identification of slip events'",
      "The first one is always spanning the entire interface and is triggered by the initial noise"),
    C("s5_event", S_PROC, "a single event (Fig. S5): a growing rupture, slip rate up to O(10 v0)",
      "supplement, Fig. S5",
      "the main rupture area with a sliding velocity going up to O(10 v0). This rupture is growing and "
      "propagating spatially", 10.0),
    C("noise_transient", S_PROC, "initial noise is not necessary; it only speeds up the transient",
      "main text 'Results'",
      "The latter is not necessary, i.e., the linear elasto-frictional instability would be triggered also by "
      "numerical noise, but it speeds up transient dynamics"),
    C("stationary", S_PROC, "reference: first and last fifths of the run have the same statistics",
      "Fig. S8, Sect. 'Statistical stationarity'",
      "It is observed that all 3 distributions, for all quantities, are essentially the same, demonstrating "
      "statistical stationarity", "stationary"),
    C("s9_power_law", S_PROC, "alpha = 8, 15, 30, 60: small events follow a power law for every alpha",
      "Fig. S9, Sect. 'effect of the threshold'",
      "First, the distribution of small events follows a power law scaling"),
    C("s9_crossover", S_PROC, "alpha = 8-60: the change of scaling of p(u) at the same scale",
      "Fig. S9, Sect. 'effect of the threshold'",
      "Second, a change in scaling law occurs around the same scale, which is related to the reflection timescale"),
    C("s9_lognormal", S_PROC, "alpha = 8-60: large events roughly log-normal (T)", "Fig. S9, Sect. 'effect of the threshold'",
      "Finally, the large propagating events are roughly log-normal distributed"),
    C("s9_max_size", S_PROC, "larger alpha, larger maximal events", "Sect. 'effect of the threshold'",
      "increasing α results in grouping events together and thus increases the maximum observed event size"),
    C("clusters", S_PROC, "most events are a single cluster", "Fig. S6",
      "It is observed that most events are composed of a single cluster (note the semi-logarithmic scale)",
      "most n_c = 1"),
)

# Numbers the report shows that the paper does not claim (not counted).
MEASUREMENTS: tuple[Claim, ...] = (
    C("fig3_peak_position", S_FIG3CD, "where the large-event peak of p(T) lies, in units of 2H/c_s",
      "Fig. 3c/3d captions",
      "The upward pointing arrows mark the values of 2H/c_s (the paper marks the time scale; it does not place "
      "the peak at it)"),
    C("fig3_peak_fit", S_FIG3CD, "fit T_peak = k (2H/c_s)^beta over the five runs", "not quantified in the paper",
      "not quantified in the paper (arrows at 2H/c_s)"),
    C("s7_peak_position", S_FIG3CD, "large-event peak of p(u) against the S7 arrows 3 v0 2H/c_s", "Fig. S7 caption",
      "the arrow indicates a slip scale η v0 2H/c_s, corresponding to a characteristic slip accumulated during the "
      "reflection timescale (... we set η = 3)", 3.0),
    C("lognormal_u", S_FIG1, "large events: u log-normal", "not claimed (the paper claims it for T and M0)",
      "the paper shows log-normal fits of p(T) and p(M0) only"),
    C("k0_mode", S_LC, "uniform (k = 0) mode of steady sliding, H = 0.1 m", "not discussed in the paper",
      "not discussed in the paper"),
)

BY_ID = {c.id: c for c in CLAIMS + MEASUREMENTS}
assert len(BY_ID) == len(CLAIMS) + len(MEASUREMENTS), "duplicate claim id"
