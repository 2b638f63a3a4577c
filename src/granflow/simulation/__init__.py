"""The time loop, its step-size policy and its named callbacks."""
