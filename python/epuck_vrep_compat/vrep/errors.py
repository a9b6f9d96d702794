"""The failure of a V-REP call."""


class VrepError(Exception):
    """A V-REP call that failed; the message is what simRosGetLastErrors reports."""
