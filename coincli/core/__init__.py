"""The physics: numbers in, records out.  No text grammar, no printing, no exit codes.

Nothing here imports the command line; numpy and scipy load only where a module needs them
(the closed forms in :mod:`coincli.core.models` run on Python floats).
"""
