"""The last check before a result is reported: finite, and not negative where it cannot be."""
import math

import pytest

from processing.diagnostics import InputError
from processing.result import LabResult, ResultValue
from processing.uncertainty import Estimate


def _result(value, unit, *, signed=False, positive=False):
    label = {"en": "x", "ru": "x"}
    rv = ResultValue("x", Estimate(value, 0.0, math.inf), unit, label, signed=signed,
                     positive=positive)
    return LabResult("lab0", "0", label, label, {}, [], {"x": rv}, source="in.toml")


@pytest.mark.parametrize("unit, what", [("kg", "mass"), ("kg*m^2", "moment of inertia"),
                                        ("N/m", "linear stiffness"), ("kg/m^3", "density")])
def test_a_negative_mass_inertia_stiffness_or_density_is_refused(unit, what):
    with pytest.raises(InputError, match=f"a {what} cannot be negative") as info:
        _result(-0.5, unit).check_sense()
    assert info.value.file == "in.toml" and "template" in info.value.fix


@pytest.mark.parametrize("value, unit, signed", [
    (0.0, "kg*m^2", False),       # "none", e.g. no flywheel needed
    (-0.5, "kg*m^2", True),       # a residual
    (-0.5, "N*m", False),         # a torque (shares a torsional stiffness's dimension)
    (-0.5, "", False),
])
def test_zero_residuals_and_signed_quantities_pass(value, unit, signed):
    _result(value, unit, signed=signed).check_sense()


@pytest.mark.parametrize("value, unit", [(0.0, ""), (-0.0185, ""), (-2.0, "rad"),
                                         (0.0, "1/s"), (-1e-9, "N*m")])
def test_a_strictly_positive_result_at_or_below_zero_is_refused(value, unit):
    """δ, an amplitude, a frequency, a torsional stiffness: never reported ≤ 0."""
    with pytest.raises(InputError, match="above zero by its nature") as info:
        _result(value, unit, positive=True).check_sense()
    assert info.value.file == "in.toml" and "template" in info.value.fix


@pytest.mark.parametrize("value, refused", [(1.58, True), (-1.58, True), (0.3, False),
                                            (-0.2, False)])
def test_a_result_declared_within_an_interval_is_refused_outside_it(value, refused):
    """A valve's timing (±90° of crank about its dead centre): outside, refused with the
    declaration's own fix; inside, reported."""
    from processing.result import Within

    label = {"en": "x", "ru": "x"}
    rv = ResultValue("x", Estimate(value, 0.0, math.inf), "", label, display_unit="rad",
                     within=Within(-math.pi / 2, math.pi / 2, "check the TDC marks"))
    result = LabResult("lab0", "0", label, label, {}, [], {"x": rv}, source="in.toml")
    if not refused:
        result.check_sense()
        return
    with pytest.raises(InputError, match=r"outside -1.571…1.571 rad") as info:
        result.check_sense()
    assert info.value.fix == "check the TDC marks"


def test_a_strictly_positive_result_above_zero_passes():
    _result(1e-12, "", positive=True).check_sense()


@pytest.mark.parametrize("value", [math.nan, math.inf])
def test_a_result_that_is_not_finite_is_refused(value):
    with pytest.raises(InputError, match="cannot be computed"):
        _result(value, "kg").check_sense()


def test_methods_disagreeing_with_a_zero_reference_are_told_in_its_unit():
    """A comparison whose reference value is exactly zero (a flat mean cycle's δ) cannot be
    put in per cent: the warning gives the difference and its bound as they are, and does
    not fail."""
    import warnings

    from processing.diagnostics import MethodsDisagreeWarning
    from processing.measurement import bi
    from processing.result import compare, flag_estimates, result_values
    from processing.uncertainty import Measured, propagate

    prop = propagate(lambda a, b: {"a": a, "b": b * 0.0},
                     {"a": Measured(0.02, 0.0005), "b": Measured(0.02, 0.0005)}, n_samples=0)
    results = result_values(prop, {"a": (bi("a", "a"), "a", ""), "b": (bi("b", "b"), "b", "")})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        flag_estimates(results, compare(prop, [("a", "b")]))
    (note,) = [w.message for w in caught if isinstance(w.message, MethodsDisagreeWarning)]
    assert "differ by +0.02," in str(note) and "%" not in str(note).split("(")[0]
