# Unicycle (V, W) to differential drive (Vl, Vr) and back (seed 003 §4.2.1, Appendix
# A.2), the ICC radius (§2.2), ensure_W (A.3: "ensures that w is respected as best as
# possible by sacrificing v") and the wheel speed to PWM map (A.3's Arduino map()).
# Speeds in cm/s, turn rates in rad/s, lengths in cm. Pure Python.


def uni_to_diff(v, w, track_cm):
    """(Vl, Vr) = ((2V - WL) / 2, (2V + WL) / 2)."""
    return (2 * v - w * track_cm) / 2, (2 * v + w * track_cm) / 2


def diff_to_uni(vl, vr, track_cm):
    """(V, W) = ((Vr + Vl) / 2, (Vr - Vl) / L)."""
    return (vr + vl) / 2, (vr - vl) / track_cm


def icc_radius(vl, vr, track_cm):
    """Signed distance from the axle's middle to the instantaneous centre of curvature,
    R = L/2 (Vl + Vr) / (Vr - Vl); None when driving straight. Vl = 0 gives L/2 (the
    seed's §2.2 says 2l: an erratum)."""
    if vr == vl:
        return None
    return track_cm / 2 * (vl + vr) / (vr - vl)


def ensure_w(v, w, track_cm, v_max, v_max_w0, w_max_v0):
    """ensure_W() of A.3: clamp V and W, convert, then shift both wheels by the same
    amount so that neither exceeds +-v_max; W is kept, V gives way. Returns (Vl, Vr)."""
    v = max(min(v, v_max_w0), -v_max_w0)
    w = max(min(w, w_max_v0), -w_max_v0)
    vl_d, vr_d = uni_to_diff(v, w, track_cm)
    hi = max(vr_d, vl_d)
    lo = min(vr_d, vl_d)
    if hi > v_max:
        return vl_d - (hi - v_max), vr_d - (hi - v_max)
    if lo < -v_max:
        return vl_d - (lo + v_max), vr_d - (lo + v_max)
    return vl_d, vr_d


def arduino_map(x, in_min, in_max, out_min, out_max):
    """Arduino's map(): long arithmetic, so the speed is truncated to an integer and the
    division truncates towards zero; no clamping (a speed below in_min maps below out_min)."""
    num = (int(x) - in_min) * (out_max - out_min)
    den = in_max - in_min
    q = abs(num) // abs(den)
    return (q if (num >= 0) == (den > 0) else -q) + out_min
