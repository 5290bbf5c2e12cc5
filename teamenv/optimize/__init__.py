"""Tournament-driven CMA-ES search over a team config's declared parameters (``teamenv optimize``).

An application above the tournaments (docs/architecture.md): imports the match runner,
tournaments and analytics; never imports ``strategy`` (a team's search space is read from its
config dataclass's field metadata, declared with ``teamenv.search_space``, which is part of
the plugin API in the core so that a team never imports the optimizer).
"""
