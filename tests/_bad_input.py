"""The property-based bad-input tests of the procedural modules, shared by tests/test_noise.py,
tests/test_patterns.py and tests/test_reaction_diffusion.py.

A case is ``(function name, parameter, strategy of bad values, call)``; a bad value must raise ValueError or
TypeError whose message names the parameter. The strategies are in tests/test_noise.py.
"""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st


def public_functions(module):
    """The public functions of a procedural module (its ``__all__``, classes and constants left out)."""
    return {n for n in module.__all__ if callable(getattr(module, n)) and not isinstance(getattr(module, n), type)}


def bad_input_tests(module, cases):
    """The two bad-input tests of ``module``: ``cases`` cover its public functions; each raises naming its parameter.

    Bind them in the test module under their own names (pytest collects them there)::

        test_bad_input_cases_cover_every_public_function, test_bad_input_raises_naming_the_parameter = \\
            bad_input_tests(module, cases)
    """
    functions = sorted({c[0] for c in cases})

    def test_bad_input_cases_cover_every_public_function():
        assert public_functions(module) == set(functions)

    @pytest.mark.parametrize("function", functions)
    @settings(max_examples=30, deadline=None)
    @given(data=st.data())
    def test_bad_input_raises_naming_the_parameter(function, data):
        """Draw one case of ``function`` and one bad value: the call raises ValueError or TypeError naming the
        parameter."""
        _, parameter, values, call = data.draw(st.sampled_from([c for c in cases if c[0] == function]), label="case")
        value = data.draw(values, label=parameter)
        with pytest.raises((ValueError, TypeError)) as caught:
            call(value)
        assert parameter in str(caught.value), (parameter, value, caught.value)

    return test_bad_input_cases_cover_every_public_function, test_bad_input_raises_naming_the_parameter
