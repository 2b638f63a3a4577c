"""Anderson acceleration (``fem/anderson.py``): on a linear contraction it reaches the fixed
point in far fewer iterations than plain iteration, and it leaves the fixed point alone."""

import numpy as np

from granflow.fem.anderson import Anderson


def _iterations(depth: int, tol: float = 1e-10) -> tuple[int, np.ndarray]:
    """x = G(x) = A x + b with a slow symmetric contraction (rates up to 0.95)."""
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(40, 40)))
    a = q @ np.diag(np.linspace(0.0, 0.95, 40)) @ q.T
    b = rng.normal(size=40)
    exact = np.linalg.solve(np.eye(40) - a, b)
    mixer = Anderson(depth, weight=lambda v: v)
    x = np.zeros(40)
    for k in range(1, 2000):
        image = a @ x + b
        if np.linalg.norm(image - x) < tol * np.linalg.norm(exact):
            return k, image
        x = mixer.mix(x, image)
    raise AssertionError("no convergence")


def test_mixing_converges_much_faster_to_the_same_fixed_point() -> None:
    plain, x_plain = _iterations(depth=0)
    mixed, x_mixed = _iterations(depth=5)
    assert plain > 300                 # 0.95^k < 1e-10 needs about 450 iterations
    assert mixed < plain / 3           # 81 against 382
    # a residual below 1e-10 |x| leaves both within 20 times that (rate 0.95) of the exact x
    assert np.allclose(x_mixed, x_plain, rtol=0, atol=40 * 1e-10 * np.linalg.norm(x_plain))


def test_a_growing_residual_restarts_the_history() -> None:
    mixer = Anderson(3, weight=lambda v: v)
    x = np.zeros(3)
    mixer.mix(x, np.array([1.0, 0.0, 0.0]))
    mixer.mix(x, np.array([0.5, 0.0, 0.0]))
    out = mixer.mix(x, np.array([4.0, 0.0, 0.0]))      # larger residual: plain iterate
    assert mixer.restarts == 1
    assert np.array_equal(out, [4.0, 0.0, 0.0])
