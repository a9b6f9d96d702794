"""The paper's fidelity study as client tools: its scenarios (``scenarios``, driven by the
``paper_scenario`` node), ``fit_noise`` (noise parameters from a bag of any e-puck) and
``sim_vs_real`` (the report). Clients: they read bags and talk ROS, and load nothing of the
simulator."""
