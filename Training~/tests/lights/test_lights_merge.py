"""The merge after a spotlight fit (merge.py, lights.md §4) and where spotlights start (starts.under_a_ceiling): the
fold itself on hand-made lights; a synthetic room lit by one spotlight, where a fit started from two spotlights shares
its disc between them and the merge with its second pass recovers the one."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights.merge import merge_spotlights
from lpnn.lights.model import Lights
from lpnn.lights.optimise import Fitter, initial_intensity
from lpnn.lights.pipeline import second_pass
from lpnn.lights.settings import MERGE_PASS, SCHEMES
from lpnn.lights.starts import SPOT_REACH, under_a_ceiling
from synthetic_room import ROOM_SIDE, lit_room

DOWN = [0.0, 0.0, -1.0]


def five_lights() -> Lights:
    """Spotlights of power 300 (colour peak 0.5), 100 and 80 within 40 units of each other, a point light of 50 beside
    them, and a spotlight of 90 far away."""
    return Lights(positions=np.array([[0.0, 0.0, 100.0], [30.0, 0.0, 100.0], [0.0, 40.0, 100.0], [10.0, 10.0, 100.0],
                                      [500.0, 0.0, 100.0]]),
                  colours=np.array([[0.5, 0.4, 0.3], [1.0, 1.0, 1.0], [1.0, 0.5, 0.5], [1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]),
                  intensities=np.array([600.0, 100.0, 80.0, 50.0, 90.0]), ambient=np.array([3.0, 2.0, 1.0]),
                  surface_values=np.array([7.0]), spot_directions=np.array([DOWN, DOWN, DOWN, [0.0, 0.0, 0.0], DOWN]),
                  radius_by_dist=np.array([0.7, 0.5, 0.9, 0.0, 0.6]))


def test_weaker_spotlights_within_the_radius_are_folded_into_the_strongest() -> None:
    lights = five_lights()
    merged = merge_spotlights(lights, 64.0)
    # the two weaker spotlights' power (100 + 80) goes into the strongest (300), in its colour: intensity (300 + 180) / 0.5
    np.testing.assert_allclose(merged.intensities, [960.0, 50.0, 90.0])
    np.testing.assert_array_equal(merged.positions, lights.positions[[0, 3, 4]])
    np.testing.assert_array_equal(merged.colours, lights.colours[[0, 3, 4]])
    np.testing.assert_array_equal(merged.radius_by_dist, [0.7, 0.0, 0.6])  # the point light stays, as it was
    np.testing.assert_array_equal(merged.spot_directions, [DOWN, [0.0, 0.0, 0.0], DOWN])
    np.testing.assert_array_equal(merged.ambient, lights.ambient)
    np.testing.assert_array_equal(merged.surface_values, lights.surface_values)
    power = lambda found: float(np.sum(found.intensities * found.colours.max(axis=1)))  # noqa: E731
    assert power(merged) == pytest.approx(power(lights))
    # within 32 units only the spotlight 30 units away is taken; at 0 none
    np.testing.assert_allclose(merge_spotlights(lights, 32.0).intensities, [800.0, 80.0, 50.0, 90.0])
    assert merge_spotlights(lights, 0.0) is lights


def test_without_spotlights_nothing_is_merged_and_a_bad_radius_is_refused() -> None:
    points = Lights(positions=np.zeros((2, 3)), colours=np.ones((2, 3)), intensities=np.array([5.0, 9.0]))
    assert merge_spotlights(points, 64.0) is points
    with pytest.raises(ValueError, match="merge radius nan"):
        merge_spotlights(five_lights(), float("nan"))
    with pytest.raises(ValueError, match="merge radius -1.0"):
        merge_spotlights(five_lights(), -1.0)


def test_the_merge_and_its_second_pass_recover_one_spotlight_where_the_fit_split_its_disc() -> None:
    """One downward spotlight lights the room; the fit starts two spotlights 38 units apart on either side of it. It
    explains the room by sharing the disc between them (each about half the power); folded and fitted again, one
    spotlight carries the light, on the true one, deterministically."""
    truth = Lights(positions=np.array([[128.0, 128.0, 220.0]]), colours=np.array([[1.0, 0.9, 0.7]]),
                   intensities=np.array([1200.0]), ambient=np.array([6.0, 6.0, 6.0]),
                   spot_directions=np.array([DOWN]), radius_by_dist=np.array([0.6]))
    model = lit_room(truth, divisions=10, pillar=False)[0]
    start = np.array([[112.0, 128.0, 200.0], [150.0, 128.0, 200.0]])

    def fit() -> tuple[Lights, Lights]:
        fitter = Fitter(model, (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0)),
                        lambda p: np.all((p > 0) & (p < ROOM_SIDE), axis=1), model.points, refresh=10)
        first = fitter.fit(initial_intensity(model, start, spots=np.ones(2, bool)), SCHEMES["mixed"]).lights
        return first, second_pass(fitter, merge_spotlights(first, 64.0), 2).lights

    split, found = fit()
    shares = np.sort(split.intensities * split.colours.max(axis=1)) / 1200.0
    assert shares[0] > 0.25 and shares[1] < 0.75  # the disc shared: neither light alone has three quarters of it
    assert found.count == 1
    assert found.intensities[0] * found.colours[0].max() == pytest.approx(1200.0, rel=0.1)
    assert np.linalg.norm(found.positions[0] - truth.positions[0]) < 12.0
    assert found.radius_by_dist[0] == pytest.approx(0.6, abs=0.05)
    visible = model.visibility(found)
    assert model.objective(found, visible).value < model.objective(split, model.visibility(split)).value
    again = fit()[1]
    np.testing.assert_array_equal(again.positions, found.positions)
    np.testing.assert_array_equal(again.intensities, found.intensities)


def test_the_second_pass_continues_the_curve_with_its_phases_after_the_first() -> None:
    truth = Lights(positions=np.array([[128.0, 128.0, 220.0]]), colours=np.ones((1, 3)), intensities=np.array([900.0]),
                   spot_directions=np.array([DOWN]), radius_by_dist=np.array([0.6]))
    model = lit_room(truth, divisions=6, pillar=False)[0]
    fitter = Fitter(model, (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0)),
                    lambda p: np.all((p > 0) & (p < ROOM_SIDE), axis=1), model.points, refresh=5)
    start = np.array([[120.0, 128.0, 200.0], [140.0, 128.0, 200.0]])
    first = fitter.fit(initial_intensity(model, start, spots=np.ones(2, bool)), SCHEMES["quick"])
    length, iterations = len(first.curve), first.iterations
    assert first.initial_lights == 2
    second = second_pass(fitter, merge_spotlights(first.lights, 64.0), len(SCHEMES["quick"]))
    assert [point.phase for point in second.curve[:length]] == [0] + [1] * (length - 2) + [1]
    assert {point.phase for point in second.curve[length:]} == {1, 2}  # its start (phase 0 + 1), its L-BFGS, its end
    iterations_seen = [point.iteration for point in second.curve]
    assert iterations_seen == sorted(iterations_seen) and second.iterations > iterations
    assert second.seconds >= first.seconds and fitter.budget == iterations + MERGE_PASS[0].iterations


def test_a_spotlight_start_hangs_under_a_ceiling_in_reach_and_not_under_the_sky() -> None:
    """Positions under a ceiling 100 units up, under one beyond SPOT_REACH, under nothing, and under a sky hole (sky 50
    units up, the ceiling beyond it 300 up), each 100 units wide (wider than the side steps): only the first may start
    a spotlight; without sky, the last may too."""
    positions = np.array([[50.0, 0.0, 0.0], [150.0, 0.0, 0.0], [250.0, 0.0, 0.0], [350.0, 0.0, 0.0]])
    ceiling = lambda p: np.array([100.0, SPOT_REACH + 1.0, np.inf, 300.0])[(p[:, 0] // 100).astype(int)]  # noqa: E731
    sky = lambda p: np.array([np.inf, np.inf, np.inf, 50.0])[(p[:, 0] // 100).astype(int)]  # noqa: E731
    assert under_a_ceiling(positions, ceiling, sky).tolist() == [True, False, False, False]
    assert under_a_ceiling(positions, ceiling, None).tolist() == [True, False, False, True]


def test_a_spotlight_start_beside_its_fixture_hangs_from_it() -> None:
    """A 16-unit panel 24 units above a start, centred 12 units beside it (as aggressor's tilted spotlights hang: the
    disc's peak, under which the start is, lies beside the panel), the sky 400 units up everywhere else: straight up the
    start sees the sky, from the side step toward the panel it sees the panel — the column ceiling_starts found it in —
    so it hangs there. Straight up alone (the rule before) it was dropped; a start with no panel within the side steps
    is still dropped."""
    panel_x = (4.0, 20.0)  # x range of the panel, at y in [-8, 8]

    def under_panel(p: np.ndarray) -> np.ndarray:
        return (p[:, 0] >= panel_x[0]) & (p[:, 0] <= panel_x[1]) & (np.abs(p[:, 1]) <= 8.0)

    ceiling = lambda p: np.where(under_panel(p), 24.0, 400.0)  # noqa: E731
    sky = lambda p: np.where(under_panel(p), np.inf, 400.0 - 1e-6)  # noqa: E731  (the sky is the first thing up there)
    starts = np.array([[-8.0, 0.0, 0.0], [-200.0, 0.0, 0.0]])
    assert not under_panel(starts).any()  # neither start is straight under the panel
    assert under_a_ceiling(starts, ceiling, sky).tolist() == [True, False]
    assert under_a_ceiling(starts, ceiling, None).tolist() == [True, True]  # without sky, the roof 400 up is in reach


def test_coincident_spotlights_of_equal_power_fold_into_the_lower_index() -> None:
    """Two spotlights at one place with the same power (200 at colour peak 1, 400 at 0.5) and a third of the same power
    50 units away: ties go to the lower index, whatever the order the lights come in (merge.py: deterministic); within
    40 units only the pair merges, within 64 the first takes in both."""
    def lights(order: list[int]) -> Lights:
        positions = np.array([[0.0, 0.0, 100.0], [0.0, 0.0, 100.0], [0.0, 50.0, 100.0]])
        colours = np.array([[1.0, 0.5, 0.5], [0.5, 0.5, 0.5], [1.0, 1.0, 1.0]])
        return Lights(positions=positions[order], colours=colours[order],
                      intensities=np.array([200.0, 400.0, 200.0])[order],
                      spot_directions=np.array([DOWN, DOWN, DOWN])[order],
                      radius_by_dist=np.array([0.4, 0.8, 0.6])[order])

    merged = merge_spotlights(lights([0, 1, 2]), 40.0)
    np.testing.assert_array_equal(merged.colours, [[1.0, 0.5, 0.5], [1.0, 1.0, 1.0]])  # the first of the pair kept
    np.testing.assert_allclose(merged.intensities, [400.0, 200.0])
    np.testing.assert_array_equal(merged.radius_by_dist, [0.4, 0.6])
    swapped = merge_spotlights(lights([1, 0, 2]), 40.0)
    np.testing.assert_array_equal(swapped.colours, [[0.5, 0.5, 0.5], [1.0, 1.0, 1.0]])  # now the other one is first
    np.testing.assert_allclose(swapped.intensities, [800.0, 200.0])
    np.testing.assert_array_equal(swapped.radius_by_dist, [0.8, 0.6])
    chained = merge_spotlights(lights([0, 1, 2]), 64.0)  # the first takes both: all within 64 units of it
    np.testing.assert_allclose(chained.intensities, [600.0])
    np.testing.assert_array_equal(chained.positions, [[0.0, 0.0, 100.0]])
