"""Shared test configuration: a hypothesis profile without deadlines (sympy timings vary),
and the tests moved out of the default run for its time (issue 39)."""

from __future__ import annotations

import os
import warnings

import pytest
from hypothesis import HealthCheck, settings

#: the default run draws the same examples every time (``derandomize``): CI on a clean clone
#: must not pass or fail by the draw (two edge cases that random draws found failed a CI run;
#: they are ``@example``s of their tests now); ``HYPOTHESIS_PROFILE=explore`` draws anew (100
#: examples where a test sets no number), to look for more
settings.register_profile("kbm", deadline=None, max_examples=25, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("explore", deadline=None, max_examples=100,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "kbm"))

#: the flows built ahead of time (:mod:`numerics.flow.aot`) cost a compilation of 10-20 s
#: per flow in each new cache folder, and many tests use one: off in the test run (and the
#: commands it starts) unless a test turns it on (``tests/test_flow_aot.py``,
#: ``tests/test_warm_path.py``)
os.environ.setdefault("KBM_AOT", "0")

#: one BLAS thread in each test process (and the commands the tests start): pytest-xdist
#: already runs a worker per core, and each worker's OpenBLAS starting a thread per core
#: made the workers fight over the cores (a 121 x 121 solve took 106 ms under that load
#: against 0.7 ms on one thread).  Set before numpy's BLAS starts where this runs first,
#: and applied by threadpoolctl where numpy was imported already.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
#: and the stationary Kramers ladder in one process (numerics.fokker_planck._ahead): the
#: workers already fill the cores; tests/test_fokker_planck_ahead.py sets two processes
os.environ.setdefault("KBM_FP_WORKERS", "1")
from threadpoolctl import threadpool_limits  # noqa: E402

threadpool_limits(1)

#: the slowest tests of the default run, marked ``slow`` here (they run with ``python -m
#: pytest -m slow``) so that the README's test command stays within 5 minutes on two cores:
#: node id -> seconds in the whole parallel run (``--durations=30``, 2026-11-26, on a
#: 2-core machine loaded about 6-fold; roughly a quarter of that on a quiet one).  Each is
#: kept, with its assertions: a kill-and-resume, Dask against the local pool, a second
#: regeneration with another hash seed, long scans and Monte Carlo byte-equality runs.
SLOW = {
    # (twelfth session, 1512 tests in 5:20-5:35 on two quiet cores in a fresh clone: seconds
    # in that run; each has a sibling of its check in the default run: the closed-form mu^2
    # line shift (test_vdp_order_2_moves_the_line_by_mu_squared_only); the averaged rate
    # against Mel'nikov-Meshkov; the energy audit of the same slides; orders 1-3 of the same
    # exact linear test; the warm cycle's refused input with the cards stored; the thermal
    # friction contract in-process (test_params_layer's friction cases); the other gaps of
    # the same fold test; the duffing-1-3 case of the same jets test; the other branches of
    # test_cycles_continuation; the pointwise Bessel sums; tests/test_sampled_cases' N = 1)
    "tests/test_spectrum_order2.py::"
    "test_order_2_error_against_the_true_cycle_falls_like_mu_cubed": 6.6,
    "tests/test_escape_averaged.py::test_averaged_rate_tends_to_kramers": 6.5,
    "tests/test_paper_sliding.py::test_results_do_not_depend_on_the_integrator": 5.0,
    "tests/test_forced_engine.py::test_linear_forced_oscillator_exact_at_every_order[4]": 4.5,
    "tests/test_line_card.py::test_refused_branch_input_is_refused_alike_with_the_cards_stored":
    5.1,
    "tests/test_noise_cli.py::test_friction_with_noise_cli": 5.6,
    "tests/test_every_cycle.py::test_both_cycles_beside_the_fold[1e-06]": 3.6,
    "tests/test_coupled_jets.py::test_equals_the_exact_engine_to_order_3[quadratic-1-2]": 3.1,
    "tests/test_cycles_continuation.py::"
    "test_unstable_branch_matches_shooting_and_reversed_time": 3.7,
    "tests/test_kbm_engine.py::test_bessel_models_agree_with_numerical_kbm": 3.5,
    "tests/test_coupled_bessel.py::"
    "test_one_slider_above_the_first_order_in_the_general_form": 3.6,
    # (then 5:04 for 1501: five more, with their siblings: the first harmonic's value at
    # mu = 20 (test_vdp_mu20_first_harmonic_value); the Ctrl-C case of test_interrupt; the
    # scipy-checked doublings of test_coupled_branch (slow since the twenty-second session: those
    # of tests/test_bifurcation_pd.py); the Duffing fold's error slopes in
    # test_forced_numerics; test_coupled_cli's lock contract)
    "tests/test_cycles_accuracy.py::"
    "test_first_harmonic_of_relaxation_cycles_matches_taylor_reference[20]": 11.3,
    "tests/test_thermal_friction_bounds.py::test_sigterm_stops_a_one_point_law_within_2_s": 4.3,
    "tests/test_forced_special.py::test_period_doublings_on_a_forced_duffing_branch": 4.0,
    "tests/test_forced_numeric.py::"
    "test_slider_error_against_shooting_falls_like_mu_to_the_order": 3.6,
    "tests/test_params_layer.py::test_lock_tongue_header_has_the_coupling_range": 3.5,
    # (eleventh session, 1460 tests in 5:12 on two quiet cores: more, each with a sibling
    # of its check in the default run: the sedf and cdc cases of the same N = 1 test; the
    # Pade test on true cycles; test_coupled_jets' equality with the exact engine; the SIGINT
    # case of the same test; test_coupled_friction's same bytes on any executor; the AOT
    # corrector's bit-identity in test_flow_aot and the warm cycle's import tests)
    "tests/test_coupled_bessel.py::"
    "test_n1_equals_the_bessel_engine[(1 - x**2)*xdot - delta*xdot*sin(k*x)]": 5,
    "tests/test_cycle_series.py::test_resum_and_radius_on_a_known_function": 5,
    "tests/test_coupled_bessel.py::test_forced_slider_in_internal_resonance_equals_the_jets": 5,
    "tests/test_interrupt.py::"
    "test_a_signal_stops_the_map_within_2_s_and_no_worker_outlives_it[15-143-SIGTERM]": 4,
    "tests/test_cycles_sweep.py::test_sweep_gives_the_same_bytes_on_every_executor": 6,
    "tests/test_warm_path.py::test_the_warm_branch_imports_no_numba_and_gives_the_same_bytes": 4,
    "tests/test_warm_path.py::test_refused_input_gives_the_same_message_with_the_cards_stored":
    60,
    "tests/test_store_resume.py::"
    "test_a_map_killed_midway_and_resumed_equals_the_uninterrupted_run": 208,
    "tests/test_coupled_jets.py::test_locking_edges_at_order_2_for_a_sine_coupling": 150,
    "tests/test_sliding_maps.py::test_dask_and_the_local_pool_give_identical_maps": 105,
    "tests/test_derivations.py::test_regeneration_is_independent_of_hash_seed": 94,
    "tests/test_cycles_search.py::test_every_cycle_of_a_brute_force_scan_is_listed[1.5-1.0]": 93,
    "tests/test_noise_cli.py::test_noise_same_bytes_for_a_seed_on_any_worker_count": 91,
    # 2026-11-26, tenth session: seconds alone; each has a faster sibling in the default run
    # (the extrapolated ensemble split into pieces equals one call; warm, cold and fresh
    # templates give the same values)
    "tests/test_noise_cli.py::test_noise_extrapolate_same_bytes_on_any_worker_count": 11,
    "tests/test_template_cache.py::"
    "test_cycle_gives_the_same_bytes_with_a_cold_and_a_warm_template_cache": 9,
    # 2026-11-26, tenth session: seconds in a whole parallel run on two quiet cores (6:03
    # for 1400 tests); each has a sibling of its check in the default run (other
    # parameters of the same test, the library-level test of the same command, or the
    # same contract checked by a faster test)
    "tests/test_noise_cli.py::test_noise_json_contract_and_boltzmann": 17,
    "tests/test_noise_cli.py::test_noise_rare_event_guard": 12,
    "tests/test_coupled_bessel.py::"
    "test_n1_equals_the_bessel_engine[-delta*x**3*sin(2*k*x) + xdot]": 8,
    "tests/test_coupled_bessel.py::"
    "test_n1_equals_the_bessel_engine[(1 - x**2)*xdot - delta*x**2*cos(k*x)]": 7,
    "tests/test_coupled_bessel.py::"
    "test_n1_equals_the_bessel_engine[-delta*x*cos(k*x) - 2*zeta*xdot]": 5,
    "tests/test_energy_shooting.py::test_delta_3_larger_mu": 7,
    "tests/test_fokker_planck_escape.py::test_escape_cli_method_fokker_planck": 7,
    "tests/test_noise_validity.py::test_escape_warns_below_two_kT": 7,
    "tests/test_store_resume.py::test_a_map_saved_as_netcdf_reads_back_in_one_line": 6,
    "tests/test_params_layer.py::test_escape_takes_T": 6,
    "tests/test_forced_numeric.py::test_command_line_slider": 5,
    "tests/test_coupled_numeric.py::test_locking_of_sine_coupled_van_der_pol_oscillators": 6,
    # and (5:25 for 1388 tests) the closed forms of the order-2 linewidth (the doctest of
    # kbm.noise.phase_diffusion.linewidth_series checks them), the shifted potential's u1 (its
    # chain-vs-jets sibling), the escape JSON (test_escape_phase_cli), the noise one-line
    # errors (test_noise_cli's), T = D/mu (friction's and escape's), the extrapolation
    # record (the two-level estimate against quadrature)
    "tests/test_spectrum_order2.py::test_closed_forms_of_the_correction": 7,
    "tests/test_coupled_constants.py::test_shifted_potential_u1_equals_fft_quadrature": 5,
    "tests/test_noise_cli.py::test_escape_json_simulated": 5,
    "tests/test_noise_validity.py::test_cli_one_line_errors": 5,
    "tests/test_params_layer.py::test_noise_takes_T_as_D_over_mu": 4,
    "tests/test_noise_extrapolation.py::"
    "test_noise_report_extrapolate_states_method_and_error": 4,
    "tests/test_coupled_bessel.py::test_chain_of_three_equals_the_jets": 85,
    "tests/test_energy_position.py::test_h_not_odd_period_orders": 84,
    "tests/test_forced_special.py::test_neimark_sacker_on_the_driven_slider": 82,
    # the next ones: seconds in a whole parallel run on a quiet 2-core machine (6:25 for
    # 1218 tests, 2026-11-26); each has a faster sibling of the same check in the default
    # run (the noise contract in-process, order 2 against Boltzmann, lower orders, the
    # other models), so the default run stays under 5 minutes
    "tests/test_paper_figures.py::test_comparison_figures_written": 13.6,
    "tests/test_stochastic_order2.py::test_cli_order_two": 12.2,
    "tests/test_coupled_constants.py::test_shifted_potential_chain_equals_the_jets": 12.1,
    "tests/test_noise_cli.py::test_noise_figure": 12.0,
    "tests/test_forced_engine.py::test_linear_forced_oscillator_exact_at_every_order[5]": 10.9,
    "tests/test_cycle_series.py::test_pade_resummed_series_against_true_cycle[2-1e-11]": 10.5,
    "tests/test_new_user.py::test_classical_kbm_far_outside_its_range_says_so": 9.7,
    "tests/test_forced_numerics.py::test_vdp_locking_boundary": 9.1,
    "tests/test_pointwise.py::test_order_2_equals_the_symbolic_bessel_sums[cdc]": 8.5,
    # (fourteenth session) the vdp stationary moments against Risken's pair at 256 x 132
    # (12 s alone); sibling in the default run: the orthonormal basis's virial at 1e-9
    # (test_fokker_planck_stationary_orthonormal::test_van_der_pol_virial_in_the_orthonormal_basis)
    "tests/test_fokker_planck_nonlinear.py::test_van_der_pol_stationary_moments_to_eight_digits": 12,
    # (fifteenth session) the turnover rate at mu = 1, which now climbs the two sink ladders
    # of the absorbing limit twice (17 s alone); siblings in the default run: the same test
    # at mu = 0.2 and the small ladders' bracket
    # (test_fokker_planck_sink::test_small_ladders_bracket_their_limit)
    "tests/test_fokker_planck_escape.py::test_turnover_converges_and_ignores_the_range[1.0]": 17,
    # (twenty-second session, 1849 tests in 15:52 on two cores loaded 7-11-fold, 536 CPU
    # seconds: seconds in that run, about a fourth on quiet cores; issue 35, "its time does
    # not grow").  Each keeps a faster sibling of its check in the default run:
    # - the 30-digit mpmath masses at the bins that end on a separatrix: the envelope against
    #   the float quadrature with the saddles as break points, across the separatrix, to 1e-8
    #   of the peak (test_envelope_boltzmann::test_issue_case_cdc_at_rest; the kT = 2 case of
    #   this test was slow already);
    # - vdp's series to mu^24 by three routes: Andersen & Geer's published coefficients
    #   (test_vdp_frequency_matches_andersen_geer_published_coefficients), the Lindstedt and KBM
    #   routes equal to mu^16 (test_lindstedt_equals_kbm_route), float against exact to mu^40;
    # - vdp mu = 1 at 25 against 34 digits: the same Taylor integrator through ``kbm cycle
    #   --digits 20``, its period to 15 digits (test_cycles_shooting::test_cli_cycle_json);
    # - the isola's four doublings by scipy's Brent on lambda_min + 1: the same scipy check at
    #   the four doublings of h = 15.9, and the one-parameter doublings of continue_coupled at
    #   h = 20 and 25 met by the period-doubling curve (tests/test_bifurcation_pd.py);
    # - the SEDF case of the origin well's MFPT: its two CDC cases, the same assertions;
    # - the averaged energy density against Boltzmann at kT = 1 within 2 %: the same test at
    #   kT = 0.25, and the envelope's bins against Boltzmann to 1e-8 of the peak across the
    #   separatrix (test_envelope_boltzmann::test_issue_case_cdc_at_rest);
    # - N = 1 of the coupled recursion to order 30 for Duffing: the same test to order 20 for
    #   van der Pol, and order 5 for four models (test_one_degree_of_freedom_is_the_one_dof_
    #   recursion)
    "tests/test_envelope_boltzmann.py::test_bins_ending_at_a_separatrix[0.6-2.4]": 27.0,
    "tests/test_cycle_series.py::test_vdp_through_eps24_three_independent_routes": 11.2,
    "tests/test_cycles_shooting.py::test_vdp_mu1_high_precision_digit_by_digit": 17.1,
    "tests/test_coupled_branch.py::"
    "test_forced_duffing_period_doublings_against_scipy_shooting": 10.4,
    "tests/test_escape_averaged.py::"
    "test_origin_well_envelope_gives_the_same_mfpt[sedf-params2-0.05]": 9.6,
    "tests/test_thermal_averaged.py::test_energy_density_is_boltzmann[1.0]": 10.3,
    "tests/test_coupled_engine.py::test_one_degree_of_freedom_to_high_orders[duffing-30]": 5.6,
}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Mark the tests of :data:`SLOW` ``slow`` (before ``-m`` selects); a listed test of a
    collected file that no longer exists is named in a warning (the list went stale); and
    put the files of :data:`HEAVY_FIRST` first, heaviest first (a stable sort: the tests of
    a file keep their order)."""
    rank = {name: i for i, name in enumerate(HEAVY_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))
    ids = {item.nodeid for item in items}
    files = {nodeid.split("::")[0] for nodeid in ids}
    for item in items:
        if item.nodeid in SLOW:
            item.add_marker(pytest.mark.slow)
    if any("::" in str(arg) for arg in config.args):  # single tests asked for by node id
        return
    stale = [n for n in SLOW if n.split("::")[0] in files and n not in ids]
    if stale:
        warnings.warn(f"tests/conftest.py SLOW lists tests that do not exist: {stale}",
                      pytest.PytestConfigWarning, stacklevel=1)


#: the test files that take longest (seconds of summed test time in a whole run, 2026-11-27,
#: two loaded cores, divided by the load), heaviest first.  pytest-xdist's ``--dist
#: loadfile`` hands whole files to the two workers in collection order (with
#: ``--no-loadscope-reorder``; its default order is by the number of tests in a file), so
#: sending the heaviest first is longest-processing-time scheduling: the two workers end
#: within about one small file of each other.  Only the order of the files changes, never
#: what a test does; a file not listed keeps its place after these.
HEAVY_FIRST = (
    "tests/test_fokker_planck.py",  # 47
    "tests/test_noise_cli.py",  # 32
    "tests/test_derivations.py",  # 22
    "tests/test_thermal_averaged.py",  # 22
    "tests/test_bifurcation_pd.py",  # 18
    "tests/test_cycles_continuation.py",  # 18
    "tests/test_comparison_fixed_delta.py",  # 17
    "tests/test_long_period.py",  # 16
    "kbm/noise/phase_diffusion.py",  # 15 (its doctest)
    "tests/test_stickslip_events.py",  # 13
    "tests/test_shooting_acceptance.py",  # 12
    "tests/test_noise_extrapolation.py",  # 11
    "tests/test_bifurcation_oned.py",  # 11
    "tests/test_branch_cli.py",  # 11
    "tests/test_interrupt.py",  # 11
    "tests/test_floors.py",  # 11
    "tests/test_import_cycles.py",  # 10
    "tests/test_paper_methods.py",  # 10
    "tests/test_fokker_planck_escape.py",  # 10
    "tests/test_cycles_accuracy.py",  # 10
    "tests/test_fokker_planck_stationary_orthonormal.py",  # 10 (fourteenth session)
    "tests/test_fokker_planck_nonlinear.py",  # 10 (fourteenth session)
    "tests/test_coupled_friction.py",  # 9
    "tests/test_latex.py",  # 9
    "tests/test_bifurcation_snl.py",  # 8
    "tests/test_spectrum_order2.py",  # 8
    "tests/test_forced_numerics.py",  # 7
    "tests/test_cycle_series.py",  # 7
    "tests/test_stochastic_order2.py",  # 7
    "tests/test_energy_maps.py",  # 6
    "tests/test_paper_sliding.py",  # 6
    "numerics/paper/errata.py",  # 6
    "tests/test_every_cycle.py",  # 6
    "tests/test_physical_axis.py",  # 6 (fourteenth session)
    "tests/test_lock_steps.py",  # 5 (fourteenth session)
)

