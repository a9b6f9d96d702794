"""A user's metric file that fails as it is read."""
raise RuntimeError("broken on import")
