"""Getting per-step messages onto the wire: the step batch and pre-serialised layouts."""
