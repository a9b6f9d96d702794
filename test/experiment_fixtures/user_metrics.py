"""A user's metric for the experiment tests."""


def score(ctx):
    """The run's seed doubled."""
    return 2.0 * ctx.seed
