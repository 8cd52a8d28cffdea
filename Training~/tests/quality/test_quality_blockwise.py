"""Blockwise reference (quality/placement/decimation/blockwise.py): the yardstick for volumes too large for the reference."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.quality.placement.decimation import blockwise
from lpnn.quality.placement.decimation.blockwise import blockwise_reference
from lpnn.quality.metric.metric import ReferenceField, placement_error
from lpnn.quality.placement.decimation.reference_fast import fast_decimation


def test_one_block_is_the_reference_itself(small_captures: dict[int, Capture]) -> None:
    capture = small_captures[2]
    field = ReferenceField.from_capture(capture)
    whole = blockwise_reference(field, capture.ids, block=1000, margin=0)
    assert whole.blocks == 1
    reference = fast_decimation(field)
    for tau in (0.005, 0.02, 0.05):
        np.testing.assert_array_equal(whole.within(tau), reference.prefix(reference.smallest_count_within(tau)))


def test_blocks_nest_cover_every_point_and_stay_near_the_tolerance(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    blocks = blockwise_reference(field, medium_capture.ids, block=5, margin=2)
    n = medium_capture.point_count
    assert blocks.blocks > 8
    np.testing.assert_array_equal(np.sort(blocks.ranking), np.arange(n))
    previous = 0
    for tau in (0.1, 0.05, 0.03, 0.02):
        kept = blocks.within(tau)
        assert kept.shape[0] >= previous  # a smaller tolerance keeps a superset
        previous = kept.shape[0]
        np.testing.assert_array_equal(kept, np.sort(blocks.ranking[:kept.shape[0]]))  # the ranking's prefix
        # Each block meets tau over its own points with margin; the union, on one mesh, lands near tau.
        assert placement_error(field, kept).mean <= 1.5 * tau
    reference = fast_decimation(field)
    # More probes than the exact reference (blocks cannot share probes across faces), but not many more.
    count = blocks.within(0.03).shape[0]
    assert reference.smallest_count_within(0.03) <= count <= 2.5 * reference.smallest_count_within(0.03)


def test_two_workers_give_the_same_answer(medium_capture: Capture) -> None:
    """Blocks are independent: decimating them in two processes changes nothing, including a block kept whole."""
    field = ReferenceField.from_capture(medium_capture)
    one = blockwise_reference(field, medium_capture.ids, block=5, margin=1)
    reported: list[tuple[int, int]] = []
    two = blockwise_reference(field, medium_capture.ids, block=5, margin=1, workers=2,
                              progress=lambda done, total: reported.append((done, total)))
    assert two.blocks == one.blocks > 8 and reported[-1] == (one.blocks, one.blocks)
    np.testing.assert_array_equal(two.entry, one.entry)
    np.testing.assert_array_equal(two.ranking, one.ranking)


def test_a_run_cut_short_resumes_from_its_checkpoint(medium_capture: Capture, tmp_path, monkeypatch) -> None:
    """Finished blocks are kept as they go; a second call decimates only the others and gives the uninterrupted
    answer. A checkpoint of other inputs (another margin) or a damaged one is started afresh."""
    monkeypatch.setattr(blockwise, "CHECKPOINT_SECONDS", 0.0)  # write after every block
    field = ReferenceField.from_capture(medium_capture)
    whole = blockwise_reference(field, medium_capture.ids, block=5, margin=1)
    checkpoint = tmp_path / "level.blockwise.npz"

    class CutShort(Exception):
        pass

    def cut_after_three(done: int, total: int) -> None:
        if done == 3:
            raise CutShort

    with pytest.raises(CutShort):
        blockwise_reference(field, medium_capture.ids, block=5, margin=1, progress=cut_after_three,
                            checkpoint=checkpoint)
    assert checkpoint.is_file()
    reported: list[int] = []
    resumed = blockwise_reference(field, medium_capture.ids, block=5, margin=1, checkpoint=checkpoint,
                                  progress=lambda done, total: reported.append(done))
    assert reported[0] == 3 and reported[-1] == whole.blocks and len(reported) == whole.blocks - 2
    np.testing.assert_array_equal(resumed.entry, whole.entry)
    np.testing.assert_array_equal(resumed.ranking, whole.ranking)

    other: list[int] = []  # another margin: the stored blocks do not apply
    blockwise_reference(field, medium_capture.ids, block=5, margin=2, checkpoint=checkpoint,
                        progress=lambda done, total: other.append(done))
    assert other[0] == 1
    checkpoint.write_bytes(b"not a checkpoint")
    damaged = blockwise_reference(field, medium_capture.ids, block=5, margin=1, checkpoint=checkpoint)
    np.testing.assert_array_equal(damaged.ranking, whole.ranking)
