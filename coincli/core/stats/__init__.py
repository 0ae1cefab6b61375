"""Counts of tosses against the models: :mod:`.counts` (the observations), :mod:`.intervals`
(Wilson and Clopper-Pearson), :mod:`.tests` (exact tests, verdicts, checks of experiments) and
:mod:`.fit` (the spread of psi and the models compared across experiments)."""
