"""Built-in sweep files (``granflow sweep NAME``)."""
