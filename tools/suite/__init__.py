"""The test runner behind ``bash tools/test``: plans the suite as independent jobs (a pytest tier
spread over the cores with xdist, one job per experiment-tier file, per gtest binary and per
rostest file), runs them side by side within the machine's cores, counts what ran against what
exists, and writes where the time went. See docs/testing.md."""
