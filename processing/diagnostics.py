"""Domain warnings and input errors.

Suspect data warns by name (a subclass of :class:`DynlabWarning`); the message says the
consequence and the remedy, in English and Russian, and reaches the report. Bad input raises
:class:`InputError`, which names the file, the field and the fix.
"""
from __future__ import annotations

import contextlib
import warnings
from dataclasses import dataclass

from .numerals import localize_numbers


class DynlabWarning(UserWarning):
    """Base of the toolkit's warnings: suspect data or a method near its limits.

    Parameters
    ----------
    message : str
        English text: what is suspect, the consequence, the remedy.
    ru : str, optional
        The same in Russian (reports with ``--lang ru``). Defaults to the English text.
    """

    code = "warning"

    def __init__(self, message: str, ru: str | None = None):
        super().__init__(message)
        self.message = message
        self.ru = ru or message

    def text(self, lang: str = "en") -> str:
        return self.ru if lang == "ru" else self.message


class AmplitudeTooLargeWarning(DynlabWarning):
    """Oscillation amplitude beyond the small-swing range of the method."""

    code = "amplitude_too_large"


class IllConditionedWarning(DynlabWarning):
    """The formula is close to a singular point: small input errors give large output errors."""

    code = "ill_conditioned"


class NonlinearityWarning(DynlabWarning):
    """Linear (GUM) uncertainty disagrees with Monte Carlo: the model is nonlinear over ± u."""

    code = "nonlinear"


class SingleReadingWarning(DynlabWarning):
    """A quantity read once: its scatter is unknown, only the instrument's limit is counted."""

    code = "single_reading"


class MethodsDisagreeWarning(DynlabWarning):
    """Two methods for one quantity differ by more than their combined expanded uncertainty."""

    code = "methods_disagree"


class InconsistentInputWarning(DynlabWarning):
    """Measured quantities that should agree with each other do not."""

    code = "inconsistent_input"


class RimSpeedWarning(DynlabWarning):
    """The flywheel rim runs faster than its material allows."""

    code = "rim_speed"


class UndersampledWarning(DynlabWarning):
    """Too few samples per tooth for the edges to be timed reliably."""

    code = "too_few_samples_per_tooth"


class TeethMiscountedWarning(DynlabWarning):
    """Teeth missed or doubled by the pulse shaper: revolutions or cycles left out."""

    code = "teeth_miscounted"


class UnequalCyclesWarning(DynlabWarning):
    """Working cycles of unequal length: the regime was not steady."""

    code = "unequal_cycles"


class GapNotFoundWarning(DynlabWarning):
    """The wheel's reference gap was not found where expected."""

    code = "gap_not_found"


class ShortRecordWarning(DynlabWarning):
    """The record holds fewer working cycles than a statistic needs."""

    code = "short_record"


class PitchErrorWarning(DynlabWarning):
    """The wheel's tooth-pitch errors are comparable with the speed fluctuation measured."""

    code = "pitch_error"


class ImbalanceWarning(DynlabWarning):
    """An engine's free forces or moments make its balance unsatisfactory."""

    code = "imbalance"


class MeanPressureDiscrepancyWarning(DynlabWarning):
    """The diagram's mean tangential pressure misses the analytic p_i·i·k/π by ≥ 3 %."""

    code = "t_mean_discrepancy"


class FlywheelNotNeededWarning(DynlabWarning):
    """The crank train alone keeps δ below the target: no flywheel is needed."""

    code = "flywheel_not_needed"


class ImplausibleValueWarning(DynlabWarning):
    """An input's magnitude lies outside what a lab bench usually measures."""

    code = "implausible_value"


class TextTruncatedWarning(DynlabWarning):
    """A text (notes, a name) too long for a report was cut."""

    code = "text_truncated"


class GaugeBackwardsWarning(DynlabWarning):
    """A dial gauge's reading falls as the load rises: it is mounted or read the wrong way."""

    code = "gauge_backwards"


class TableCurvatureWarning(DynlabWarning):
    """A load–deflection table bends significantly: its straight-line slope is load-dependent."""

    code = "table_curvature"


class LargeHysteresisWarning(DynlabWarning):
    """The loop between loading and unloading is wider than a sound rig shows."""

    code = "large_hysteresis"


class AmplitudeDependentDampingWarning(DynlabWarning):
    """A free decay's logarithmic decrement changes along the record: the damping depends on
    the amplitude, and one δ for the whole record is an average over amplitudes."""

    code = "amplitude_dependent_damping"


class UnclosedLoopWarning(DynlabWarning):
    """A load–deflection loop does not return to its start: a residual twist at zero load."""

    code = "unclosed_loop"


class BaselineDriftWarning(DynlabWarning):
    """A record's baseline moves more than the fit's baseline follows (creep, drift)."""

    code = "baseline_drift"


class StiffnessRatioWarning(DynlabWarning):
    """A dynamic stiffness out of its usual proportion to the static one."""

    code = "stiffness_ratio"


class LowConfidenceTraceWarning(DynlabWarning):
    """A share of a trace read off a paper record's image is unreliable: lost, crossing
    another trace, faint or blotted."""

    code = "low_confidence_trace"


class UnevenTimeBaseWarning(DynlabWarning):
    """The time marks of a paper record are not evenly spaced: the paper's speed changed, or
    the photograph's perspective is not fully taken out."""

    code = "uneven_time_base"


class BlurredMarksWarning(DynlabWarning):
    """The pips of a paper record's time or TDC marks are blurred into single blobs: where
    each mark rises, and so the marks' place against the trace, is uncertain."""

    code = "blurred_marks"


class ContactLossWarning(DynlabWarning):
    """The valve drive loses contact (the force falls to zero while the valve is open): the
    kinematic chain breaks and closes again with an impact."""

    code = "contact_lost"


class FreeOscillationWarning(DynlabWarning):
    """The drive's free oscillations are too few or too weak on a record for a sound
    frequency."""

    code = "free_oscillation_poor"


class ClippedRecordWarning(DynlabWarning):
    """A channel sat at its converter's or amplifier's limit: its peaks and the orders it
    carries are cut, its readings low."""

    code = "clipped_record"


class NoiseFloorWarning(DynlabWarning):
    """A band reading rests on the record's broadband floor (sensor noise, or broadband
    vibration) rather than on the engine's orders."""

    code = "noise_floor"


class CutCylinderWarning(DynlabWarning):
    """A record marked with a cylinder cut shows no cut cylinder, shows another one than
    stated, or has no healthy record at its speed to be compared with."""

    code = "cut_cylinder"


class RecordBandwidthWarning(DynlabWarning):
    """A record's sample rate does not reach a band the method reads: what lies above its
    Nyquist frequency is missing from the reading."""

    code = "record_bandwidth"


class NoMarksWarning(DynlabWarning):
    """A record has no usable TDC marks: what needs no crank angle is reduced, and the
    results that need the marks are left out."""

    code = "no_tdc_marks"


class SpeedDisagreesWarning(DynlabWarning):
    """The TDC marks' speed and the tachometer's differ beyond the tachometer's error."""

    code = "speed_disagrees"


class FilmAmplitudeWarning(DynlabWarning):
    """The amplitude read off a film is less certain than its limit
    (:data:`processing.vision.video.AMPLITUDE_LIMIT`): the marker swings too little in the
    picture for its arc's radius to be found."""

    code = "film_amplitude_uncertain"


class IrregularFrameRateWarning(DynlabWarning):
    """A film's frame intervals vary (a phone's variable frame rate): each frame's own
    timestamp is used, but a film whose clock stutters times the swing less well."""

    code = "irregular_frame_rate"


class DroppedFramesWarning(DynlabWarning):
    """The camera dropped frames: gaps of about two frame intervals in the film's
    timestamps (each frame's time is used, but the swing is followed less closely there),
    or, where the times claim a constant rate, the swing's phase jumping by a whole interval
    (the frames after it are timed that much later)."""

    code = "dropped_frames"


class HiddenDropsWarning(DynlabWarning):
    """A film whose times claim a constant rate cannot show a dropped frame: a single one's
    step in the swing's phase would stand under what the search needs to find it, and one
    dropped mid-film would move the period beyond its stated uncertainty. Not that a frame
    was dropped: that, were one dropped, nothing here would tell."""

    code = "hidden_drops"


class NominalFrameRateWarning(DynlabWarning):
    """A film's container holds no time for its frames (AVI): they are taken 1/rate apart,
    and a variable rate or a dropped frame would go unseen."""

    code = "nominal_frame_rate"


class TorsiographResponseWarning(DynlabWarning):
    """A torsiograph's own natural frequency is not 5–10 times below the frequencies it
    records: their amplitudes rest on its transfer function's correction."""

    code = "torsiograph_response"


class MixedOrdersWarning(DynlabWarning):
    """A torsiogram is not dominated by one order: counting its oscillations (K = ν/n) does not
    give the resonating order; the harmonic analysis does."""

    code = "mixed_orders"


class UnresolvedResonanceWarning(DynlabWarning):
    """A resonance peak is narrower than the speed step between the records around it, or fell
    between them: its speed and order are uncertain."""

    code = "resonance_unresolved"


class ResonanceBeyondSweepWarning(DynlabWarning):
    """An order rises steeply at an end of a speed sweep: a resonance lies just beyond it."""

    code = "resonance_beyond_sweep"


@dataclass(frozen=True)
class Notice:
    """A warning as it is stored in a result and printed in a report."""

    code: str
    message: str
    ru: str

    def text(self, lang: str = "en") -> str:
        return self.ru if lang == "ru" else self.message

    def to_dict(self) -> dict:
        return {"code": self.code, "message": self.message, "message_ru": self.ru}


@contextlib.contextmanager
def collect_notices():
    """Record the toolkit's warnings raised inside the block (other warnings pass through).

    Yields a list that fills with :class:`Notice` items, each warning once, in order.
    """
    notices: list[Notice] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DynlabWarning)
        yield notices
    for w in caught:
        if isinstance(w.message, DynlabWarning):
            m = w.message
            notice = Notice(type(m).code, m.message, localize_numbers(m.ru, "ru"))
            if notice not in notices:
                notices.append(notice)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


class Reason(ValueError):
    """A reason found deep down (a header that does not read, no trace on a sheet, too few
    time marks), in English and in Russian (``ru``), for the :class:`InputError` its caller
    raises with it: each language's text is made where the detail is known.

    >>> r = Reason("3 time mark(s) found", "найдено отметок времени: 3")
    >>> str(r), r.ru
    ('3 time mark(s) found', 'найдено отметок времени: 3')
    """

    def __init__(self, reason: str, ru: str):
        super().__init__(reason)
        self.ru = ru


class InputError(ValueError):
    """Bad input: names the file, the field, what is wrong and how to fix it.

    Parameters
    ----------
    problem : str
        What is wrong, with the offending value.
    fix : str
        What the user should do.
    file : str, optional
        The measurement file.
    field : str, optional
        Dotted path of the field in the file, e.g. ``trifilar.l``.
    ru : (str, str), optional
        The problem and the fix in Russian (the command line's ``--lang ru``, or a Russian
        locale). A message without them is printed in English in either language.

    Examples
    --------
    >>> e = InputError("l must be > 0 mm, got -1", "measure the thread again",
    ...                file="a.toml", field="trifilar.l",
    ...                ru=("l должна быть > 0 мм, а не -1", "измерьте нить заново"))
    >>> e.line("en")
    "error: a.toml, field 'trifilar.l': l must be > 0 mm, got -1. Fix: measure the thread again"
    >>> e.line("ru")
    "ошибка: a.toml, поле 'trifilar.l': l должна быть > 0 мм, а не -1. Как исправить: измерьте нить заново"
    """

    def __init__(self, problem: str, fix: str, *, file: str | None = None,
                 field: str | None = None, ru: tuple[str, str] | None = None):
        self.problem, self.fix, self.file, self.field, self.ru = problem, fix, file, field, ru
        super().__init__(str(self))

    def __str__(self) -> str:
        return self.text("en")

    def text(self, lang: str = "en") -> str:
        """The message in ``lang`` (English where it has no Russian): where, what, the fix."""
        ru = lang == "ru" and self.ru is not None
        field = ("поле '{}'" if ru else "field '{}'").format(self.field) if self.field else None
        where = ", ".join(p for p in (self.file, field) if p)
        return f"{where + ': ' if where else ''}{self.reason(lang)}"

    def reason(self, lang: str = "en") -> str:
        """What is wrong and the fix in ``lang``, without where (a cell of a table that
        already says where)."""
        ru = lang == "ru" and self.ru is not None
        problem, fix = self.ru if ru else (self.problem, self.fix)
        return f"{problem}. {'Как исправить' if ru else 'Fix'}: {fix}"

    def line(self, lang: str = "en") -> str:
        """The one line the command line prints for it, in ``lang`` where it can."""
        return f"{'ошибка' if lang == 'ru' and self.ru is not None else 'error'}: {self.text(lang)}"

    def located(self, file: str) -> InputError:
        """The same error, attributed to ``file`` if it had no file yet."""
        return InputError(self.problem, self.fix, file=self.file or file, field=self.field,
                          ru=self.ru)


def first(values) -> float:
    """The first element of an array of offending values, for a message."""
    import numpy as np  # here, not above: the command line's list and help need no numpy

    return float(np.ravel(values)[0])


def check_positive(name: str, value, unit: str) -> None:
    """Raise :class:`InputError` unless every element of ``value`` is > 0."""
    import numpy as np

    if isinstance(value, (int, float)) and value > 0:   # one plain number: no array made
        return
    bad = ~(np.asarray(value, dtype=float) > 0)
    if np.any(bad):
        raise InputError(f"{name} must be > 0 {unit}, got {first(np.asarray(value)[bad]):g}",
                         f"give {name} in {unit} (SI)")
