"""The papers' experiments reproduced on simulated data (gyrocore.paper): exact recovery where the
mathematics is exact, and the papers' qualitative claims and orderings elsewhere."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from gyrocore import paper, sim


@pytest.fixture(scope="module")
def hong_cal() -> paper.HongCalibration:
    return paper.hong_calibration()


@pytest.fixture(scope="module")
def hong_t1() -> paper.HongTable1:
    return paper.hong_table_1()


@pytest.fixture(scope="module")
def hong_sens() -> paper.HongTable1Sensitivity:
    return paper.hong_table_1_sensitivity()


@pytest.fixture(scope="module")
def hdr_fig() -> paper.HdrFigures:
    return paper.hdr_figures()


@pytest.fixture(scope="module")
def hdr_tab() -> paper.HdrTables:
    return paper.hdr_tables()


@pytest.fixture(scope="module")
def fog_table() -> paper.FogRotaryTable:
    return paper.fog_rotary_table(runs=80)


def test_rate_reference_recovers_hong_section_3_1_exactly(hong_cal: paper.HongCalibration) -> None:
    # s = -10 %, b = 0.1 rad/s: s_bar = 1/(1+s) = 1.1111..., b_bar = -b/(1+s) = -0.1111... (Hong eq 3).
    assert hong_cal.rate.s_bar == pytest.approx(1.0 / 0.9, rel=1e-12)
    assert hong_cal.rate.b_bar == pytest.approx(-0.1 / 0.9, rel=1e-12)
    assert hong_cal.errors(hong_cal.rate) == pytest.approx((0.0, 0.0), abs=1e-9)


def test_heading_reference_recovers_them_within_the_integration_error(hong_cal: paper.HongCalibration) -> None:
    # The paper's heading fit was off by 4.8 % (s) and 20.26 % (b); an exact fit, noise-free, is
    # limited only by integrating the 100 Hz gyro between the 20 Hz reference samples.
    s_error, b_error = hong_cal.errors(hong_cal.heading)
    assert s_error < 0.1 and b_error < 0.1
    # With the XV3500's noise both fits still find s and b within a few percent.
    assert max(hong_cal.errors(hong_cal.rate_noisy) + hong_cal.errors(hong_cal.heading_noisy)) < 5.0


def test_hong_table_1_proposed_is_best_and_calibration_beats_pure_integration(hong_t1: paper.HongTable1) -> None:
    mean = {m: hong_t1.mean_error(m) for m in hong_t1.PAPER}
    # The paper's claims that the simulation reproduces: the combination is best, each part helps.
    assert mean["proposed"] == min(mean.values())
    assert mean["self-calibration"] < 0.6 * mean["pure integration"]
    assert mean["threshold filter"] < mean["pure integration"]
    assert mean["proposed"] < mean["threshold filter"]
    # The self-calibration finds the XV3500's scale error and bias (2.53 %, 0.75 deg/s).
    s = np.mean([c.scale_error for c in hong_t1.calibrations])
    b = np.mean([math.degrees(c.bias) for c in hong_t1.calibrations])
    assert s == pytest.approx(0.0253, abs=0.002) and b == pytest.approx(0.75, abs=0.02)


def test_hong_table_1_threshold_gains_more_on_a_quieter_gyro(hong_t1: paper.HongTable1) -> None:
    # The README's explanation of the threshold's small gain: it is the noise (as large as the
    # threshold) that passes it. With a tenth of the noise bandwidth, the threshold gains more.
    quiet = paper.hong_table_1(sensor=sim.sensor("xv3500", bandwidth_hz=2.0))
    assert quiet.mean_error("threshold filter") < 0.8 * hong_t1.mean_error("threshold filter")
    # The notes state the noise and the leak of the gyro simulated, not the XV3500's.
    assert "0.31 deg/s rms" in hong_t1.table() and "lets 82 %" in hong_t1.table()
    assert "0.10 deg/s rms" in quiet.table() and "lets 4 %" in quiet.table()
    assert quiet.mean_error("pure integration") == pytest.approx(hong_t1.mean_error("pure integration"), rel=0.05)


def test_hong_table_1_threshold_cannot_beat_the_bias_leak(hong_sens: paper.HongTable1Sensitivity) -> None:
    # What the threshold leaves of pure integration's error is never below the fraction of a
    # residual bias it lets through (deadband.bias_leak), and it shrinks as the noise does.
    for turn in hong_sens.turns_deg:
        ratios = [hong_sens.ratio("threshold filter", turn, b) for b in hong_sens.bandwidths_hz]
        assert all(r >= hong_sens.leak(b) for r, b in zip(ratios, hong_sens.bandwidths_hz))
        assert ratios == sorted(ratios, reverse=True)
    # At the XV3500's noise (Figure 8a: 0.31 deg/s rms) the leak is 82 %: the threshold keeps
    # more than 80 % of the error whatever the turns, against the paper's 47 %.
    stated = hong_sens.bandwidths_hz[0]
    assert hong_sens.noise_rms_dps(stated) == pytest.approx(0.31, abs=0.005)
    assert hong_sens.leak(stated) > 0.8
    assert min(hong_sens.ratio("threshold filter", t, stated) for t in hong_sens.turns_deg) > 0.8


def test_hong_table_1_has_the_papers_order_only_with_a_quiet_gyro_and_small_turns(
    hong_sens: paper.HongTable1Sensitivity,
) -> None:
    order = {(t, b): hong_sens.has_paper_order(t, b) for t, b in hong_sens.tables}
    # Noise of 0.13 deg/s and less (3 Hz bandwidth and less, under half the threshold): the
    # paper's order with turns of 20 degrees and less. (With 45-degree turns it depends on the
    # seeds: threshold and self-calibration are within a few percent there.)
    assert all(order[(t, b)] for t in (20.0, 10.0) for b in (3.0, 2.0, 1.0))
    # Never with the 90-degree turns, where the scale error dominates, and never at the stated
    # noise or at 10 Hz bandwidth, whatever the turns.
    assert not any(order[(90.0, b)] for b in hong_sens.bandwidths_hz)
    assert not any(order[(t, b)] for t in hong_sens.turns_deg for b in (20.0, 10.0))
    assert hong_sens.noisiest_with_paper_order_dps(90.0) is None
    noisiest = hong_sens.noisiest_with_paper_order_dps(20.0)
    assert noisiest is not None and hong_sens.noise_rms_dps(3.0) <= noisiest <= hong_sens.noise_rms_dps(5.0)
    # Self-calibration does not depend on the noise: its gain is set by the turns.
    for turn in hong_sens.turns_deg:
        cal = [hong_sens.ratio("self-calibration", turn, b) for b in hong_sens.bandwidths_hz]
        assert max(cal) - min(cal) < 0.05


def test_hdr_minus_i_tracks_the_drift_on_straight_driving(hdr_fig: paper.HdrFigures) -> None:
    i_c = 0.0422  # deg/s, Table III
    for method in ("without", "with"):
        # -I oscillates about the drift by about one increment (HDR section 4.2.3's discussion).
        assert hdr_fig.tracking_rms(method) < 3 * i_c


def test_hdr_figure_3_peak_is_twenty_increments_above_the_drift(hdr_fig: paper.HdrFigures) -> None:
    # Without the attenuator and with the turn switch off, each of the 20 steps of curving adds i_c
    # to -I (eq 4): the peak is the drift at the start of the curve plus 20 i_c (paper: 1.2 deg/s).
    start = np.searchsorted(hdr_fig.t, hdr_fig.curve[0])
    expected = math.degrees(hdr_fig.drift[start]) + 20 * 0.0422
    assert hdr_fig.peak("without") == pytest.approx(expected, abs=2 * 0.0422)
    assert hdr_fig.peak("with") < hdr_fig.peak("without") - 10 * 0.0422


def test_hdr_figure_5_attenuator_shrinks_the_area_after_the_curve(hdr_fig: paper.HdrFigures) -> None:
    # "The area between the -I curve and the drift curve is much smaller" with the attenuator.
    assert hdr_fig.area("with") < 0.5 * hdr_fig.area("without")


def test_hdr_tables_improve_every_set_several_fold(hdr_tab: paper.HdrTables) -> None:
    for table, drives in hdr_tab.tables.items():
        assert len(drives) == (9 if table == "Table II" else 5)
        without = np.mean([d.without.ne_psi_deg_per_min for d in drives])
        with_hdr = np.mean([d.with_hdr.ne_psi_deg_per_min for d in drives])
        # The paper: 2.2 -> 0.28 and 2.9 -> 0.46 deg/min; a 9.2x and 6.9x mean improvement.
        assert with_hdr < without / 2.5, (table, without, with_hdr)
        assert hdr_tab.improvement(table) > 2.5
    assert [d.spec.minutes for d in hdr_tab.tables["Table II"]][:3] == [19.4, 24.3, 20.0]


def test_hdr_tables_set_the_papers_printed_figures_beside_ours(hdr_tab: paper.HdrTables) -> None:
    # The paper's column holds what Tables II and IV print, not ratios or means recomputed from
    # their rounded entries (City 1 reads 17 / 3.1 = 5.5 but prints 5.4x; the means 61 and 92).
    rows = {line.split("  ")[0].strip(): line for line in hdr_tab.table().splitlines()}
    for drive, factor in (("City 1", "5.4x"), ("Rural 1", "7.7x"), ("Highway 1", "29x"), ("Highway Mix", "4.4x"),
                          ("City 2", "6.7x"), ("City 3", "4.3x")):
        assert rows[drive].split()[-2] == factor, rows[drive]
    summary = {r.quantity: r.paper for r in hdr_tab.rows()}
    assert summary["Table II: mean E_psi without HDR"] == "61"
    assert summary["Table II: mean E_psi with HDR"] == "7.0"
    assert summary["Table IV: mean E_psi without HDR"] == "92"


def test_hdr_tables_state_the_cabin_temperatures_they_drew(hdr_tab: paper.HdrTables) -> None:
    starts = [d.start_temperature for drives in hdr_tab.tables.values() for d in drives]
    assert 5.0 <= min(starts) and max(starts) <= 15.0
    assert "between 5 and 15 degC" in hdr_tab.table()
    # The paper's static bias test lasted 30 s (HDR section 2); ours is 20 s, and the note says so.
    assert hdr_tab.rest == 20.0 and "20 s static bias test (the paper's T_bias: 30 s" in hdr_tab.table()


def test_fog_rotary_table_finds_eq_5_and_eq_6_brings_turns_within_a_quarter_degree(
    fog_table: paper.FogRotaryTable,
) -> None:
    # The simulated FOG's scale error is the paper's eq 5, so the fit must find it.
    assert fog_table.slope_deg_per_c() == pytest.approx(-0.52, abs=0.02)
    assert fog_table.offset_deg() == pytest.approx(19.23, abs=0.6)
    # FOG section 3: after eq 6, "less than +-0.25 deg in all cases" (on another warm-up session).
    errors = fog_table.corrected_errors_deg()
    assert len(errors) == 160 and np.all(np.abs(errors) < 0.25)
    before = np.array([t.error_deg for t in fog_table.fit.turns])
    assert np.abs(before).max() > 2.0


def test_fog_square_path_return_orientation_within_one_degree() -> None:
    r = paper.fog_square_path(runs=12, calibration_runs=80)
    assert len(r.cw) == len(r.ccw) == 12
    # FOG Figure 5: the gyro's return orientation errors within +-1 deg; without eq 6 the scale
    # error of the warm-up shows (a 360 deg lap reads 360 (1 + s)).
    assert r.largest() < 1.0
    assert np.mean(np.abs(r.cw_raw)) > 2 * np.mean(np.abs(r.cw))


def test_hong_allan_reproduction_reads_the_xv3500() -> None:
    r = paper.hong_allan(gyros=3, runs=1, hours=24.0)
    assert len(r.arw_deg_per_sqrt_h) == 3
    assert r.arw == pytest.approx(2.5, rel=0.1)
    assert "17.99" in r.table()


def test_every_reproduction_prints_paper_beside_ours_and_plots(
    tmp_path: Path,
    hong_cal: paper.HongCalibration,
    hong_t1: paper.HongTable1,
    hong_sens: paper.HongTable1Sensitivity,
    hdr_fig: paper.HdrFigures,
    hdr_tab: paper.HdrTables,
    fog_table: paper.FogRotaryTable,
) -> None:
    printed = {
        "1.111": hong_cal, "1.6675": hong_t1, "0.47 / 0.69": hong_sens, "much smaller": hdr_fig, "9.2": hdr_tab,
        "19.23": fog_table,
    }
    for paper_value, result in printed.items():
        text = result.table()
        assert "paper" in text and "ours" in text and paper_value in text
        png = result.plot(tmp_path / f"{type(result).__name__}.png")
        assert png is not None and png.read_bytes()[:4] == b"\x89PNG"
    assert not list(tmp_path.glob(".*tmp"))


def test_reproduce_creates_the_figure_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    paper.reproduce("hong-calibration", out_dir=tmp_path / "figures" / "hong")
    assert (tmp_path / "figures" / "hong" / "hong_calibration.png").read_bytes()[:4] == b"\x89PNG"
    assert "1.111" in capsys.readouterr().out


def test_reproduce_says_the_data_are_simulated_and_with_which_seed(capsys: pytest.CaptureFixture[str]) -> None:
    paper.reproduce("hdr-figures", out_dir=None)
    out = capsys.readouterr().out
    assert "simulated data (no real log), seed 0 (each further run or drive the next one); " in out
    assert "gyrocore.paper.hdr_figures(seed=N) reruns it from another" in out


def test_the_simulation_page_names_every_reproduction_and_its_figure() -> None:
    page = (Path(__file__).parents[2] / "docs" / "simulation.md").read_text(encoding="utf-8")
    for name, (_, figure) in paper.REPRODUCTIONS.items():
        assert f"| `{name}` |" in page and f"| `{figure}` |" in page, name


def test_the_simulation_page_states_what_the_reproductions_print(
    hong_cal: paper.HongCalibration, hong_t1: paper.HongTable1, hdr_fig: paper.HdrFigures, hdr_tab: paper.HdrTables
) -> None:
    # docs/simulation.md's "ours" column, as rounded there, from the same runs (seed 0); the FOG
    # rows are left out for time (9 s at their defaults).
    page = (Path(__file__).parents[2] / "docs" / "simulation.md").read_text(encoding="utf-8")

    def ne(table: str, which: str) -> float:
        return float(np.mean([getattr(d, which).ne_psi_deg_per_min for d in hdr_tab.tables[table]]))

    stated = [f"{hong_cal.rate.s_bar:.4f}, {hong_cal.rate.b_bar:.4f}",
              "with XV3500 noise {:.2f} %, {:.2f} %".format(*hong_cal.errors(hong_cal.heading_noisy))]
    stated += [f"| {hong_t1.mean_error(m):.2f} / {hong_t1.std_error(m):.2f} |" for m in paper.HongTable1.PAPER]
    stated += [f"{ne(t, 'without'):.2f} / {ne(t, 'with_hdr'):.2f} deg/min; {hdr_tab.improvement(t):.1f}x"
               for t in ("Table II", "Table IV")]
    stated += [f"{hdr_fig.peak('without'):.2f} deg/s",
               f"{hdr_fig.area('without'):.1f} deg without, {hdr_fig.area('with'):.1f} deg with "
               f"({hdr_fig.area('with') / hdr_fig.area('without'):.2f}x)"]
    allan_logs = paper.hong_allan()  # about 2 s
    bias = allan_logs.bias_instability_deg_per_h
    stated.append(f"{allan_logs.arw:.2f} deg/sqrt(h), {allan_logs.bias_instability:.1f} deg/h "
                  f"({min(bias):.1f} .. {max(bias):.1f} per log)")
    assert [s for s in stated if s not in page] == []


def test_the_xv3500_preset_cites_the_sections_its_values_come_from() -> None:
    # Hong section 4.1 gives the 100 Hz sampling; section 2.2's rate table spans +-100 deg/s.
    source = sim.sensor("xv3500").source
    assert "100 Hz (4.1)" in source and "+-100 deg/s (the rate table's span in 2.2)" in source


def test_every_file_the_equations_page_points_to_exists() -> None:
    root = Path(__file__).parents[2]
    page = (root / "docs" / "equations.md").read_text(encoding="utf-8")
    paths = re.findall(r"`((?:rust|python|tests)/[\w/.]+)`", page)
    assert "python/gyrocore/calibration/least_squares.py" in paths
    assert [p for p in paths if not (root / p).is_file()] == []


def test_reproduce_help_says_seed_time_and_where_the_figures_go(capsys: pytest.CaptureFixture[str]) -> None:
    from gyrocore.cli import main

    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "simulated data (seed 0)" in text and "about 15 s" in text
    assert "default: the current folder" in text


def test_reproduce_refuses_an_unknown_name() -> None:
    with pytest.raises(ValueError, match="unknown reproduction 'hdr-figure-9'"):
        paper.reproduce("hdr-figure-9")
    assert set(paper.REPRODUCTIONS) >= {"hong-calibration", "hong-table-1", "hdr-figures", "hdr-tables",
                                        "fog-rotary-table", "fog-square-path", "hong-allan",
                                        "hong-table-1-sensitivity"}
