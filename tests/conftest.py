"""Suite-wide settings: machines here are shared and their speed swings, so no property test may
fail for taking longer than Hypothesis's default 200 ms on one example (speed is measured in bench/)."""
from hypothesis import settings

settings.register_profile("shared-machine", deadline=None)
settings.load_profile("shared-machine")
