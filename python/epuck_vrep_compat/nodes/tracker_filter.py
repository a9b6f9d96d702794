"""A constant-velocity Kalman filter of the operator on the floor: state (x, y, vx, vy).

Prediction over dt with white-noise acceleration of spectral density q (m^2/s^3):

    x' = F x,   F = [[I, dt I], [0, I]]
    P' = F P F^T + q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]

Each sensor's position measurement z (2,) with covariance R updates it (H = [I 0]); a
measurement whose Mahalanobis distance exceeds the gate is refused (another person, a robot).

What the filter believes is not all of the error: the sensors' biases (a blob box's centre is
not the body's, a laser cluster may be one leg, the Kinect's window sees his surface) do not
average out as independent noise, and the estimate is read a step later than it is made.
:func:`published_covariance` adds them to the position covariance the tracker reports (not to
the filter's, whose gains stay those of the sensors' noise): b^2 I (the biases' size) and
(tau v)(tau v)^T (the lag tau at the estimated velocity v, along it).
"""
import numpy as np

H = np.hstack((np.eye(2), np.zeros((2, 2))))


class OperatorFilter:
    """The operator's position and velocity with their covariance."""

    def __init__(self, accel_density=4.0, initial_speed_sigma=1.0, gate_sigmas=4.0):
        self.q = float(accel_density)
        self.initial_speed_sigma = float(initial_speed_sigma)
        self.gate2 = float(gate_sigmas) ** 2
        self.x = None
        self.P = None
        self.t = None

    @property
    def started(self) -> bool:
        return self.x is not None

    def start(self, t, z, r):
        self.x = np.array([z[0], z[1], 0.0, 0.0])
        self.P = np.zeros((4, 4))
        self.P[:2, :2] = r
        self.P[2:, 2:] = np.eye(2) * self.initial_speed_sigma ** 2
        self.t = t

    def predict(self, t):
        """Advance to time t (no-op backwards)."""
        dt = t - self.t
        if dt <= 0:
            return
        f = np.eye(4)
        f[0, 2] = f[1, 3] = dt
        i2 = np.eye(2)
        q = self.q * np.block([[dt ** 3 / 3 * i2, dt ** 2 / 2 * i2], [dt ** 2 / 2 * i2, dt * i2]])
        self.x = f @ self.x
        self.P = f @ self.P @ f.T + q
        self.t = t

    def update(self, z, r) -> bool:
        """Fuses a position measurement; False if it fell outside the gate."""
        innovation = np.asarray(z, dtype=float) - H @ self.x
        s = H @ self.P @ H.T + np.asarray(r, dtype=float)
        if float(innovation @ np.linalg.solve(s, innovation)) > self.gate2:
            return False
        k = self.P @ H.T @ np.linalg.inv(s)
        self.x = self.x + k @ innovation
        self.P = (np.eye(4) - k @ H) @ self.P
        self.P = 0.5 * (self.P + self.P.T)
        return True


def published_covariance(p, x, bias_sigma_m=0.0, lag_s=0.0):
    """The (2, 2) position covariance to report: the filter's P[:2, :2] plus the biases'
    b^2 I and the lag's (tau v)(tau v)^T, v the estimated velocity x[2:]."""
    v = np.asarray(x[2:4], dtype=float) * float(lag_s)
    return (np.asarray(p, dtype=float)[:2, :2] + float(bias_sigma_m) ** 2 * np.eye(2)
            + np.outer(v, v))
