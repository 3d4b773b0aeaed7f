"""The labs dynlab knows — id, module and title — readable without importing any lab, so that
``dynlab list`` and ``--help`` answer at once. Each lab's :data:`SPEC` takes its title from
here."""
from __future__ import annotations

from typing import NamedTuple


class Entry(NamedTuple):
    """One lab: the module that reduces it and its title in English and Russian."""

    module: str
    title: dict[str, str]


CATALOGUE: dict[str, Entry] = {
    "lab1": Entry("labs.lab1_inertia", {
        "en": "Moments of inertia of engine parts",
        "ru": "Определение моментов инерции деталей двигателя"}),
    "lab2": Entry("labs.lab2_conrod", {
        "en": "Reducing the connecting-rod mass",
        "ru": "Приведение масс шатуна"}),
    "lab3": Entry("labs.lab3_speed_irregularity", {
        "en": "Speed irregularity of the engine on a steady regime",
        "ru": "Определение неравномерности хода двигателя на установившемся режиме"}),
    "lab4": Entry("labs.lab4_vibration", {
        "en": "Engine vibration on the test bench",
        "ru": "Изучение вибраций двигателя в стендовых условиях"}),
    "lab5": Entry("labs.lab5_valve_stiffness", {
        "en": "Stiffness of the valve-train parts",
        "ru": "Исследование жесткости деталей механизма газораспределения двигателя"}),
    "lab6": Entry("labs.lab6_valve_dynamics", {
        "en": "Valve-train oscillations on a running engine",
        "ru": "Исследование колебаний клапанного механизма двигателя"}),
    "lab7": Entry("labs.lab7_torsiograph", {
        "en": "Torsional vibration of the crankshaft (torsiograph)",
        "ru": "Экспериментальное исследование крутильных колебаний коленчатого вала"}),
    "lab8": Entry("labs.lab8_balancing", {
        "en": "Balancing a two-cylinder in-line engine",
        "ru": "Исследование системы уравновешивания двухцилиндрового рядного двигателя"}),
    "lab9": Entry("labs.lab9_damper", {
        "en": "Internal-friction (rubber) torsional dampers",
        "ru": "Экспериментальное исследование демпферов внутреннего трения"}),
    "dyncalc": Entry("labs.dyncalc", {
        "en": "Dynamic calculation of the crank mechanism",
        "ru": "Динамический расчёт кривошипно-шатунного механизма"}),
}
"""Every lab, in the manual's order (the coursework last)."""


def title(lab_id: str) -> dict[str, str]:
    """The title of lab ``lab_id``, for its :class:`~processing.measurement.LabSpec`."""
    return CATALOGUE[lab_id].title
