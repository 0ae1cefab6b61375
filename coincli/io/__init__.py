"""Text to and from objects, without typer: the one grammar of values, stdin batches, files,
and the writers of every output format."""
