"""The finite-vigor toss (Section 3 of the paper): one toss, many tosses, phase maps, launch
distributions and simulated runs, caught without bouncing."""
