# Lane filter of the pool cleaner (seed 000 §5.4): a 2-state Kalman filter on
# (d, phi), d the distance to the reference wall, phi the path angle (d grows by
# DS_M * phi per sonar sample). Gains follow the seed's off-line recursion, so the
# board needs no matrix inversion and CPython tests can compare them with the seed's
# tables. Pure Python: runs on the board and under CPython.
try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


DS_M = 0.15  # travel per 500 ms sonar sample at 0.3 m/s (seed 000 §4.3, eq. 4.15)
R_M2 = 0.3  # sonar noise, "variance sigma = .3" (§5.3)
P0_D_M2 = 0.2  # prior on d after a reversal: N(d_ref, 0.2) (§5.4, Table 5.1)
P0_PHI_RAD2 = 0.0348  # prior on phi: 3.48e-2 (§5.4)
Q_D_M2 = 0.1  # process noise: "guessed" in the thesis; these two values reproduce
Q_PHI_RAD2 = 0.0523  # the code's kappa1/kappa2 tables within 5e-5 (see docs/pool_cleaner.md)
GAIN_STEPS = const(30)  # "stabilized after about thirty steps" (§5.4): K_30 on is constant


def gain_schedule(steps=GAIN_STEPS, ds_m=DS_M, r_m2=R_M2, p0=(P0_D_M2, P0_PHI_RAD2), q=(Q_D_M2, Q_PHI_RAD2)):
    """Gains (k_d, k_phi) for samples 0..steps of a run, by the recursion of §5.4:

    Sigma_0^-1 = Sigma^-1 + H' R^-1 H,  Sigma_i+1^-1 = (A Sigma_i A' + Q)^-1 + H' R^-1 H,
    K_i = Sigma_i H' R^-1, with A = [[1, ds], [0, 1]], H = [1, 0]; written in the
    equivalent predict/update form. Entry i < 30 is the code's kappa1[i], kappa2[i];
    entry 30 its KAPP1/KAPP2."""
    p_dd, p_dp, p_pp = p0[0], 0.0, p0[1]
    k_d = []
    k_phi = []
    for i in range(steps + 1):
        if i:  # predict: A P A' + Q
            p_dd = p_dd + 2.0 * ds_m * p_dp + ds_m * ds_m * p_pp + q[0]
            p_dp = p_dp + ds_m * p_pp
            p_pp = p_pp + q[1]
        s = p_dd + r_m2
        kd = p_dd / s
        kp = p_dp / s
        k_d.append(kd)
        k_phi.append(kp)
        # update: P - K H P
        p_pp = p_pp - kp * p_dp
        p_dp = p_dp - kd * p_dp
        p_dd = p_dd - kd * p_dd
    return k_d, k_phi


class LaneFilter:
    """(d_m, phi_rad) with the gain schedule restarting at every run, as the seed's
    State1/State2 do (the state after a reversal is only known through its prior)."""

    def __init__(self):
        self.k_d, self.k_phi = gain_schedule()
        self.n = 0  # samples since the run's first one
        self.d_m = 0.0
        self.phi_rad = 0.0

    def start(self, ref_m, phi0_rad, z_m=None):
        """First sample of a run: psi_0 = alpha + K_0 (z - H alpha), alpha = (ref, phi0)."""
        self.n = 0
        self.d_m = ref_m if z_m is None else ref_m + self.k_d[0] * (z_m - ref_m)
        self.phi_rad = phi0_rad + (0.0 if z_m is None else self.k_phi[0] * (z_m - ref_m))

    def predict(self, dphi_rad, ds_m=DS_M):
        """One sample later: the steering turn dphi first, then ds of travel (B of
        eq. 5.26 with the turn from the measured law instead of u/W)."""
        self.n += 1
        self.phi_rad += dphi_rad
        self.d_m += ds_m * self.phi_rad

    def innovation(self, z_m):
        return z_m - self.d_m

    def update(self, z_m):
        i = self.n if self.n < GAIN_STEPS else GAIN_STEPS
        e = z_m - self.d_m
        self.d_m += self.k_d[i] * e
        self.phi_rad += self.k_phi[i] * e
