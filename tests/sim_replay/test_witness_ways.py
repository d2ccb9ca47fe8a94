"""The ground truth credits a road user's braking to a vehicle's act only where their ways through
the junction cross or join (sim_replay/witness.ways_meet): a main-road car on the far side of the
road from a car turning left out of a side road was not made to brake by it, whatever made it
brake in the simulation (HC 172 asks the emerging driver to give way to traffic it would cut
across or join, not to traffic it never meets)."""

import pytest

from sim_replay.witness import ways_meet

# (vehicle's way, other's way, meet?) in left-hand traffic; a way is (arm in, arm out)
LEFT_HAND = [
    (("north", "east"), ("east", "west"), False),   # turning left; the other passes on the far side
    (("north", "east"), ("west", "east"), True),    # turning left into the lane the other drives on
    (("north", "east"), ("south", "north"), False),
    (("north", "east"), ("east", "north"), False),  # the other turns right into the arm V left
    (("north", "south"), ("east", "west"), True),   # straight across both lanes of the main road
    (("north", "south"), ("west", "east"), True),
    (("north", "west"), ("east", "west"), True),    # turning right joins the far lane
    (("north", "west"), ("west", "east"), True),    # ... across the near one
    (("north", "west"), ("south", "north"), True),  # a right turn crosses oncoming traffic
    (("north", "south"), ("north", "east"), False), # the same arm in: a queue, not a conflict
]


@pytest.mark.parametrize("mine, theirs, meet", LEFT_HAND)
def test_ways_through_a_left_hand_junction(mine, theirs, meet):
    assert ways_meet(mine, theirs, lefthand=True) is meet
    assert ways_meet(theirs, mine, lefthand=True) is meet      # symmetric


def test_right_hand_traffic_mirrors_the_left_turn():
    # in right-hand traffic the short turn is to the right: north to west meets nobody from the east
    # going south... but an east-to-west car does join its exit
    assert ways_meet(("north", "west"), ("east", "south"), lefthand=False) is False
    assert ways_meet(("north", "west"), ("east", "west"), lefthand=False) is True
    assert ways_meet(("north", "east"), ("east", "west"), lefthand=False) is True


def test_an_arm_the_map_does_not_name_is_taken_to_meet():
    assert ways_meet(("north", "north-east"), ("east", "west")) is True
