"""ModelStructure/InitialUnknowns of modelDescription/modelDescription.xml against FMI 2.0
(2.0.5, section 2.2.8) and against the FMU itself.

The standard's rules:
- InitialUnknowns lists exactly the outputs with initial = "approx" or "calculated", the
  calculated parameters, and the continuous-time states and state derivatives (from
  <Derivatives>) with initial = "approx" or "calculated", each once, ordered by index.
- `dependencies` names the Knowns of Initialization Mode the Unknown depends on: the inputs,
  the variables with initial = "exact" and the independent variable; ordered by index.
  Absent, it means all Knowns; empty, none. `dependenciesKind`, if present, has one entry per
  dependency.
A variable without `initial` takes the default of its causality and variability (FMI 2.0,
2.2.7): "exact" for parameters and for constant outputs and locals; "calculated" for
calculated parameters, other outputs and other locals; none for inputs and the independent
variable.

The FMU then shows that the listed dependencies are exactly the real ones: from an operating
point with a parameter file whose extensions make every input act on every channel, changing
one Known before initialization changes in Initialization Mode exactly the Unknowns that list
it.
"""

import json
import math
import xml.etree.ElementTree as ET

import pytest

import magic_formula as mf
from conftest import REPO
from fmu_helpers import Tire

MODEL_DESCRIPTION = REPO / "modelDescription" / "modelDescription.xml"
# dependenciesKind values of the FMI 2.0 schema (fmi2ModelDescription.xsd, InitialUnknowns).
DEPENDENCIES_KINDS = {"dependent", "constant", "fixed", "tunable", "discrete"}


def default_initial(causality, variability):
    """FMI 2.0's `initial` of a variable that does not give one (None: not allowed)."""
    if causality == "parameter":
        return "exact"
    if causality in ("output", "local"):
        return "exact" if variability == "constant" else "calculated"
    if causality == "calculatedParameter":
        return "calculated"
    return None  # input, independent


def variables():
    """{index: (name, causality, initial)} of modelDescription.xml, index from 1."""
    root = ET.parse(MODEL_DESCRIPTION).getroot()
    out = {}
    for i, sv in enumerate(root.find("ModelVariables").findall("ScalarVariable"), start=1):
        causality = sv.get("causality", "local")
        variability = sv.get("variability", "continuous")
        out[i] = (sv.get("name"), causality, sv.get("initial") or default_initial(causality, variability))
    return out


def unknowns(section):
    """[(index, dependencies or None, dependenciesKind or None)] of ModelStructure/section."""
    root = ET.parse(MODEL_DESCRIPTION).getroot()
    listed = []
    for u in root.find("ModelStructure").find(section).findall("Unknown"):
        deps, kinds = u.get("dependencies"), u.get("dependenciesKind")
        listed.append((
            int(u.get("index")),
            None if deps is None else [int(d) for d in deps.split()],
            None if kinds is None else kinds.split(),
        ))
    return listed


def derivative_pairs():
    """{derivative index: state index} of the <Derivatives> unknowns."""
    root = ET.parse(MODEL_DESCRIPTION).getroot()
    svs = root.find("ModelVariables").findall("ScalarVariable")
    return {i: int(svs[i - 1].find("Real").get("derivative")) for i, _, _ in unknowns("Derivatives")}


def knowns_in_initialization(vars_):
    return {i for i, (_, causality, initial) in vars_.items()
            if causality in ("input", "independent") or initial == "exact"}


def test_initial_unknowns_are_the_ones_the_standard_lists():
    vars_ = variables()
    ders = derivative_pairs()
    approx_or_calculated = {i for i, (_, _, initial) in vars_.items() if initial in ("approx", "calculated")}
    expected = {i for i, (_, causality, _) in vars_.items() if causality == "output"} & approx_or_calculated
    expected |= {i for i, (_, causality, _) in vars_.items() if causality == "calculatedParameter"}
    expected |= (set(ders) | set(ders.values())) & approx_or_calculated
    listed = [i for i, _, _ in unknowns("InitialUnknowns")]
    assert listed == sorted(expected), (
        f"InitialUnknowns lists {[vars_[i][0] for i in listed]}, "
        f"the standard's list is {[vars_[i][0] for i in sorted(expected)]}"
    )


def test_initial_unknown_dependencies_are_knowns_of_initialization_mode():
    vars_ = variables()
    knowns = knowns_in_initialization(vars_)
    # Here: the 7 inputs and the 41 parameters (no independent variable is declared).
    assert len(knowns) == 48, sorted(vars_[i][0] for i in knowns)
    for index, deps, kinds in unknowns("InitialUnknowns"):
        name = vars_[index][0]
        assert deps is not None, f"{name}: dependencies absent (all Knowns); this FMU lists them"
        not_known = [vars_[d][0] if d in vars_ else d for d in deps if d not in knowns]
        assert not_known == [], f"InitialUnknown {name} depends on {not_known}, not Knowns in Initialization Mode"
        assert deps == sorted(set(deps)), f"{name}: dependencies not strictly ordered by index: {deps}"
        if kinds is not None:
            assert len(kinds) == len(deps), f"{name}: {len(kinds)} dependenciesKind for {len(deps)} dependencies"
            assert set(kinds) <= DEPENDENCIES_KINDS, f"{name}: dependenciesKind {kinds}"


# The operating point: loaded, slipping, cambered; conditions away from the nominal ones.
BASE_INPUTS = {"Fz": 6000.0, "alpha": 0.08, "kappa": 0.05, "gamma": math.radians(4.0),
               "vx": 20.0, "p": 2.3e5, "T_tread": 315.0}
CHANGED_INPUTS = {"Fz": 6500.0, "alpha": 0.1, "kappa": 0.07, "gamma": math.radians(3.0),
                  "vx": 25.0, "p": 2.5e5, "T_tread": 325.0}
# Every condition extension and combined slip on every channel, so that vx, p, T_tread act
# on all three outputs and alpha on Fx; relaxation lengths too (steady in initialization).
EVERY_CHANNEL = {
    "combined_slip": {"B": 8.0, "C": 1.1},
    "inflation_pressure": {"k": 0.3, "d": -0.12},
    "speed_dependence": {"v": -0.06},
    "temperature": {"w": 0.25, "Topt_degC": 30.0, "k": 0.15},
    "relaxation_length": {"sigma_m": 0.5},
}


@pytest.fixture(scope="module")
def parameter_file(tmp_path_factory):
    params = mf.paper_table()
    params["extensions"] = {
        "nominal": {"pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 40.0},
        **{channel: EVERY_CHANNEL for channel in ("Fx", "Fy", "Mz")},
    }
    path = tmp_path_factory.mktemp("structure") / "every_extension.json"
    path.write_text(json.dumps(params))
    return str(path)


def changed_value(name, start):
    """A valid value of the Known `name` (start value `start`), different from its base
    value, that acts when the Known acts at the operating point."""
    if name in CHANGED_INPUTS:
        return CHANGED_INPUTS[name]
    special = {
        "isoSignConvention": True,
        "parameterFile": "",  # the paper's table without extensions
        "Fz_max": 5000.0,  # below Fz: the load is clamped
        "gamma_max": math.radians(3.0),  # below gamma: the camber is clamped
    }
    if name in special:
        return special[name]
    start = float(start)  # a coefficient
    return start * 1.02 if start != 0.0 else 1e-3


def initial_values(unzipdir, model_description, names, knowns):
    """The Unknowns `names` in Initialization Mode with the Knowns set to `knowns`."""
    tire = Tire(unzipdir, model_description, "structure", logging_on=False)
    try:
        tire.fmu.setupExperiment(startTime=0.0)
        tire.set(**knowns)
        tire.fmu.enterInitializationMode()
        return dict(zip(names, tire.get(*names)))
    finally:
        tire.free()


def test_initial_unknowns_depend_on_exactly_the_listed_knowns(unzipdir, model_description, parameter_file):
    vars_ = variables()
    knowns = sorted(knowns_in_initialization(vars_))
    listed = {vars_[i][0]: {vars_[d][0] for d in deps} for i, deps, _ in unknowns("InitialUnknowns")}
    names = list(listed)
    starts = {v.name: v.start for v in model_description.modelVariables}
    base = {**BASE_INPUTS, "parameterFile": parameter_file}
    at_base = initial_values(unzipdir, model_description, names, base)
    wrong = []
    for k in knowns:
        known = vars_[k][0]
        changed = initial_values(unzipdir, model_description, names,
                                 {**base, known: changed_value(known, starts[known])})
        for u in names:
            acts = changed[u] != at_base[u]
            if acts != (known in listed[u]):
                wrong.append(f"{u}: {'changes' if acts else 'does not change'} with {known} "
                             f"({at_base[u]!r} -> {changed[u]!r}), "
                             f"{'listed' if known in listed[u] else 'not listed'}")
    assert wrong == [], "InitialUnknowns dependencies differ from the FMU:\n" + "\n".join(wrong)
