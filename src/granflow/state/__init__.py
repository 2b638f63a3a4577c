"""What a run's checkpoint may hold: each part's share of the state, declared beside the part
and checked in one place (``spec.py``). The ground floor: every layer that saves state
declares its share with it."""
