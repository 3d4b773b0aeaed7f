"""The options of ``dynlab synth``, checked against what each lab's scene models before
anything is written: one table for every lab, so that no scene is asked for a record it
cannot make (a sample rate of zero, a decay of no period) or one that fills the memory.

Each bound says why it is there: the instrument the scene models (lab 3's sound card), the
physics it holds to (lab 5's Coulomb friction against its load programme), what the record
must hold for the lab's method (three extrema of a decay), or the size of what is written.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from processing.diagnostics import InputError


@dataclass(frozen=True)
class Bound:
    """The values an option may take for one lab's scene, in the option's unit.

    Parameters
    ----------
    low, high : float
        The range, both ends included (``high`` excluded where ``open_high``).
    why : str
        What sets the range, for the message.
    whole : bool
        Whole numbers only.
    open_high : bool
        ``high`` itself is out.
    """

    low: float
    high: float
    why: str
    whole: bool = False
    open_high: bool = False

    def holds(self, value: float) -> bool:
        if self.whole and value != int(value):
            return False
        return self.low <= value and (value < self.high if self.open_high else
                                      value <= self.high)

    def text(self) -> str:
        return f"{self.low:g} to {self.high:g}" + (" (not included)" if self.open_high else "")


@dataclass(frozen=True)
class Option:
    """A numeric option of ``dynlab synth``: its flag, the unit it is given in, and its bounds
    per lab (the labs whose ``write_synthetic`` takes it); a key ``"lab9 paper"`` holds for
    lab 9 when ``write_synthetic``'s switch ``paper`` is on, in place of ``"lab9"``."""

    flag: str
    unit: str
    bounds: dict[str, Bound]

    def bound(self, lab: str, given: dict) -> Bound | None:
        """The bound of ``lab`` under the switches ``given`` turns on (the most specific)."""
        keys = [k for k in self.bounds if k.split()[0] == lab
                and all(given.get(switch) for switch in k.split()[1:])]
        return self.bounds[max(keys, key=len)] if keys else None


SNR = Bound(-20.0, 200.0, "below −20 dB the noise is ten times the signal and no record of "
                          "it can be read; 200 dB is below a double's rounding")

OPTIONS = {
    "snr_db": Option("--snr", "dB", {lab: SNR for lab in ("lab3", "lab4", "lab6", "lab7",
                                                          "lab9")}),
    "pitch_error_deg": Option("--pitch-error", "°", {"lab3": Bound(
        0.0, 0.3, "the scene's wheel keeps each tooth within a twentieth of its 6° pitch",
        open_high=True)}),
    "sample_rate": Option("--sample-rate", "kHz", {
        "lab3": Bound(8.0, 192.0, "the scene's sensor is recorded by a sound card, 8 to 192 "
                                  "kHz"),
        "lab6": Bound(2.0, 200.0, "below 2 kHz the valve's oscillation (up to about 700 Hz) "
                                  "is not sampled; 200 kHz resolves it to a hundredth of "
                                  "its period"),
        "lab7": Bound(2.0, 40.0, "below 2 kHz the torsiograph's 1.5 ms time marks fall "
                                 "between samples; above 40 kHz modelling its sweep takes "
                                 "more than 1 GB of memory"),
        "lab9": Bound(2.0, 200.0, "2 kHz gives a period of the ring's 150–260 Hz decay 8 "
                                  "samples, 200 kHz 800, far past what its decrement needs"),
    }),
    "runs": Option("--runs", "", {
        "lab5": Bound(1, 20, "a loading run is the method's whole table; 20 is a day's work",
                      whole=True),
        "lab9": Bound(1, 20, "the static loop needs a run; 20 is a day's work", whole=True),
    }),
    "friction": Option("--friction", "N", {"lab5": Bound(
        0.0, 500.0, "at half the programme's 1000 N the joints' friction holds the chain "
                    "still over most of its loads")}),
    "contact": Option("--contact", "µm", {"lab5": Bound(
        0.0, 200.0, "a push rod's ball ends flatten by tens of µm at 1000 N; past 200 µm it "
                    "is no Hertzian contact")}),
    "lash": Option("--lash", "µm", {"lab5": Bound(
        0.0, 1000.0, "a valve train's clearance is 0.1 to 0.5 mm")}),
    "periods": Option("--periods", "", {
        "lab9": Bound(2.0, 20.0, "the decrement needs three extrema, two periods; by 20 "
                                 "periods a decay of δ ≥ 0.7 has fallen to a millionth, under "
                                 "any noise"),
        "lab9 paper": Bound(3.0, 20.0, "the paper record is read as four maxima, three periods "
                                       "long; by 20 periods a decay of δ ≥ 0.7 has fallen to a "
                                       "millionth"),
    }),
    "amplitude_exponent": Option("--amplitude-exponent", "", {"lab9": Bound(
        -1.0, 2.0, "in δ(A) = δ₀(A/φ₀)^p a p below −1 raises the decrement so fast as the "
                   "swing dies that the ring stops oscillating within two periods; above 2 "
                   "it drops so fast that the ring rings on undamped")}),
}
"""Every numeric option, by the keyword of ``write_synthetic`` it sets."""


def check_options(lab: str, given: dict) -> None:
    """Refuse an option value the lab's scene does not model.

    Parameters
    ----------
    lab : str
        The lab id.
    given : dict
        ``write_synthetic``'s keywords as the command line gives them, in the options' units
        (:data:`OPTIONS`; the switches, such as ``paper``, choose a bound; the others are not
        looked at).

    Raises
    ------
    InputError
        A value that is not finite, or outside the lab's :class:`Bound`, naming the option,
        the range and why.
    """
    for name, value in given.items():
        option = OPTIONS.get(name)
        bound = None if option is None else option.bound(lab, given)
        if bound is None:
            continue
        unit = f" {option.unit}" if option.unit else ""
        if not math.isfinite(value) or not bound.holds(value):
            what = "a whole number from" if bound.whole else "from"
            shown = f"{value:g}" if isinstance(value, float) else str(value)
            raise InputError(f"{option.flag} {shown}{unit} is out of what {lab}'s scene "
                             f"models: {bound.why}",
                             f"give {option.flag} {what} {bound.text()}{unit}")
