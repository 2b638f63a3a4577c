"""The time loop, its step-size policy and its observers."""
