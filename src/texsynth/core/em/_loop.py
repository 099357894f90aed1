"""The EM loop of patch-energy synthesis and its robust (IRLS) weights.

Every method that minimises a patch energy alternates two steps (Kwatra et
al. 2005, Algorithm 1): the E-step sets the image to the (weighted) average of
the neighbourhoods matched to it, the M-step matches every neighbourhood of the
image to its nearest neighbourhood of the exemplar (or of an interpolated set,
Ruiters et al. 2010). :func:`expectation_maximization` runs that alternation
with the steps supplied by the method; :func:`irls_weights` are the weights
of Section 3.1 that make the quadratic E-step minimise the robust energy
``sum_p ||x_p - z_p||^r``.

References
----------
.. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
   for example-based synthesis", ACM TOG 24(3), 2005, pp. 795-802.
   :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

__all__ = ["expectation_maximization", "irls_weights", "IRLS_EXPONENT"]

#: r of Section 3.1, the default robust exponent (the paper's 0.8).
IRLS_EXPONENT = 0.8


def irls_weights(rho, r=IRLS_EXPONENT, eps2=0.0):
    """IRLS weights of Section 3.1: ``ω_p = (r/2) (ρ_p + ε²)^((r-2)/2)``.

    With these weights the quadratic energy ``Σ ω_p ρ_p`` majorises the robust
    energy ``Σ (ρ_p + ε²)^(r/2)`` of eq. 1 at the current ``ρ_p = ||x_p - z_p||²``,
    so the weighted E-step never raises it. ``ε²`` keeps the weight of a
    perfect match finite.
    """
    return (r / 2.0) * (rho + eps2) ** ((r - 2.0) / 2.0)


def expectation_maximization(x, state, rho, e_step, m_step, energy, *, max_iterations, tolerance,
                             r=IRLS_EXPONENT, eps2=0.0, on_iteration=None):
    """The alternation of Algorithm 1 (Kwatra et al. 2005), shared by every method that minimises a patch energy.

    Texture optimization and Ruiters et al.'s interpolation (which plugs in its
    own search and pixel update) both run this loop.

    Parameters
    ----------
    x : numpy.ndarray or None
        The current image (None before the first E-step of a bootstrap).
    state, rho
        The current neighbourhoods ``z_p`` (whatever ``m_step`` returns) and
        their squared distances ``ρ_p`` (None for a random start: every
        ``ω_p = 1`` then).
    e_step : callable
        ``e_step(state, omega, iteration) -> x``: minimise the weighted energy over ``x``.
    m_step : callable
        ``m_step(x, state) -> (state, rho, changed)``: the nearest neighbourhoods of ``x``.
    energy : callable
        ``energy(rho, x) -> float``: the energy after an M-step (also the place to log it).
    max_iterations : int
        At most this many E-steps.
    tolerance : float or None
        Stop when ``E`` falls by at most this fraction of its previous value
        (None: run every iteration unless the ``z_p`` stop changing).
    r, eps2 : float
        IRLS exponent and ``ε²`` (:func:`irls_weights`).
    on_iteration : callable, optional
        ``on_iteration(iteration, energy, stop)`` after every M-step of the loop.

    Returns
    -------
    x, state, rho
        After the last E-step and the M-step that followed it.
    iterations : int
    converged : bool
        True if the loop ended because the ``z_p`` no longer changed (the paper's criterion).
    """
    energies = [] if rho is None else [energy(rho, x)]
    iterations, converged = 0, False
    for iterations in range(1, max_iterations + 1):
        omega = None if rho is None else irls_weights(rho, r, eps2)
        x = e_step(state, omega, iterations - 1)
        state, rho, changed = m_step(x, state)
        energies.append(energy(rho, x))
        # the paper stops when {z_p} no longer changes; we also stop when E has stopped falling
        flat = (tolerance is not None and len(energies) >= 2
                and energies[-2] - energies[-1] <= tolerance * abs(energies[-2]))
        stop = not changed or flat
        if on_iteration is not None:
            on_iteration(iterations - 1, energies[-1], stop)
        if stop:
            converged = not changed
            break
    return x, state, rho, iterations, converged
