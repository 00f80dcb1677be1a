"""The single-track step-steer example (demo/single_track.py): its steady yaw rate against
linear single-track theory with the FMU's own cornering stiffnesses, and co-simulation's
deviation from Model Exchange growing with the communication step."""

import math
import sys

from conftest import REPO

sys.path.insert(0, str(REPO / "demo"))
import single_track as st  # noqa: E402


def test_single_track_steady_state_and_co_simulation_delay(fmu_path):
    res = st.run(fmu_path, None, steps=(0.005, 0.04))
    check(res)


def test_single_track_with_the_fmi3_fmu_runs_as_with_fmi2(fmu_path, fmu3_path):
    """The same example on the FMI 3.0 archive: the same checks, and the same numbers."""
    res3 = st.run(fmu3_path, None, steps=(0.04,))
    check(res3)
    res2 = st.run(fmu_path, None, steps=(0.04,))
    for k in range(3):
        assert (res3["me"][k] == res2["me"][k]).all()
        assert (res3["cs"][0.04][k] == res2["cs"][0.04][k]).all()
    assert res3["c_front"] == res2["c_front"]


def check(res):
    t, r, ay = res["me"]
    # Steady state: the linear theory's yaw rate u delta / (L + K u^2), the understeer gradient
    # K from the axle cornering stiffnesses the FMU's directional derivatives give. At 1 deg
    # of steer the slip angles stay below 0.5 deg, where the tire is linear to 0.1 %.
    assert abs(r[-1] - res["r_linear"]) <= 1e-3 * res["r_linear"], (r[-1], res["r_linear"])
    assert 0 < res["k_us"] < 0.01, "an understeering car"
    assert math.isclose(ay[-1], st.SPEED * r[-1], rel_tol=1e-6), "steady: a_y = u r"
    # The hand-checked stiffness: BCD at the axle's load, twice (two tires), per rad.
    fz_kn = st.FZ_FRONT / 1000.0
    bcd = 1078.0 * math.sin(1.82 * math.atan(0.208 * fz_kn)) * 180.0 / math.pi
    assert math.isclose(res["c_front"], 2.0 * bcd, rel_tol=1e-12)
    # Co-simulation reaches the same steady state, but deviates from Model Exchange more,
    # the longer its communication step.
    devs = {}
    for h, (tc, rc, _) in res["cs"].items():
        assert math.isclose(rc[-1], r[-1], rel_tol=1e-6)
        devs[h] = st.deviation(res["me"], tc, rc)
    if 0.005 in devs:
        assert devs[0.005] < 0.1 * devs[0.04], devs
    assert devs[0.04] > math.radians(0.1), devs
