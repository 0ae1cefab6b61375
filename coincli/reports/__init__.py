"""What each command prints, from typed inputs: one module per command family, each returning
:class:`coincli.io.table.Result` objects that :mod:`coincli.cli` writes and :mod:`coincli.api`
returns as rows."""
