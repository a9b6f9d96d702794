"""The real e-puck of the paper's section 4.1 as noise parameters: each number, unit and source.

Sources: "Integrating a V-REP simulated mobile robot into ROS" (the e-puck paper), Table 1
(accelerometer while driving straight, real and V-REP rows) and section 4.1's proximity test
(sensor 0 wrong in 61 of 380 readings in open space). Where the paper gives no number the value
is ours and says so.

No double counting: what the accelerometer shows while driving is the body's true acceleration
plus the sensor's own noise. Wheel slip (relative SD s per wheel per step) makes the forward
speed jitter by v·s/√2 per step, so the finite-difference acceleration has SD v·s/dt on x (and
about v·(v·s√2/b) on y, under 0.001 m/s² here). The sensor's own SD is therefore the paper's
total less that part, in quadrature, at the paper's speed and the default step:
σ_sensor,x = √(σ_Table1,x² − (v·s/dt)²). At another speed or step the total differs accordingly
(as on the real robot, whose vibration grows with speed).
"""
import math

# Table 1, "real" row: mean and SD of the accelerometer while driving straight [m/s²].
TABLE1_REAL_MEAN_M_S2 = (-0.05254, -0.26087, 9.68479)
TABLE1_REAL_STDDEV_M_S2 = (0.03559, 0.03079, 0.04930)
# Table 1, "sim" row (V-REP, whose accelerometer reads -g on z at rest) [m/s²].
TABLE1_VREP_MEAN_M_S2 = (-0.00045, -0.00010, -9.81005)
TABLE1_VREP_STDDEV_M_S2 = (0.03630, 0.00215, 0.02562)

GRAVITY_M_S2 = 9.81                 # the model's g (epuck_model.hpp)
PAPER_SPEED_M_S = 0.04              # the straight drive of the measurement [m/s]
DEFAULT_STEP_S = 0.05               # V-REP's default step [s]

# Relative SD of each wheel's speed per step [1]. Ours: the e-puck's steppers hardly slip on a
# flat floor; 2 % makes odometry drift visibly while its acceleration jitter at 4 cm/s
# (v·s/dt = 0.016 m/s²) stays well inside Table 1's x spread, which is the total of both.
WHEEL_SLIP_STDDEV = 0.02

# Accelerometer bias [m/s²]: Table 1's real means minus the noise-free reading (0, 0, g) while
# driving straight at constant speed. It stands for the sensor's offset and gain error and the
# tilt of mounting and floor (the paper blames the wooden floor for y); a tilt's rotation of the
# body's own acceleration into other axes is below 0.001 m/s² at these speeds, so a constant
# per-axis bias models what the paper measured.
ACCEL_BIAS_M_S2 = (TABLE1_REAL_MEAN_M_S2[0], TABLE1_REAL_MEAN_M_S2[1],
                   TABLE1_REAL_MEAN_M_S2[2] - GRAVITY_M_S2)


def motion_stddev_m_s2(speed_m_s: float, slip: float, step_s: float) -> float:
    """SD of the x acceleration that wheel slip alone makes at a constant commanded speed."""
    return speed_m_s * slip / step_s


def sensor_stddev_m_s2(total, motion) -> float:
    """The sensor's own SD so that it and the motion's add up to ``total`` (in quadrature)."""
    return math.sqrt(max(total ** 2 - motion ** 2, 0.0))


# Accelerometer SD of the sensor itself [m/s²]: Table 1's real SD less the slip's part on x.
ACCEL_STDDEV_M_S2 = (
    sensor_stddev_m_s2(TABLE1_REAL_STDDEV_M_S2[0],
                       motion_stddev_m_s2(PAPER_SPEED_M_S, WHEEL_SLIP_STDDEV, DEFAULT_STEP_S)),
    TABLE1_REAL_STDDEV_M_S2[1], TABLE1_REAL_STDDEV_M_S2[2])

# Gyroscope SD [rad/s]: ours (the e-puck 1 has no gyroscope; the e-puck 2's is of this order).
GYRO_STDDEV = 0.005

# IR: probability that a reading is wrong [1]: sensor 0 of the paper's robot, 61/380 = 0.16.
IR_PROBABILITY = 0.16
# IR error size, mean and SD [m] (range_noise.hpp: |mean + SD·N(0,1)|, one-sided as the real
# errors). Ours: the paper shows the histogram (Fig. 5a) without its figures; a few millimetres,
# with mean >= 3 SD so the folding at zero changes nothing measurable.
IR_MEAN_M = 0.006
IR_STDDEV_M = 0.002
