"""Tournament-driven CMA-ES search over a team config's declared parameters (``teamenv optimize``).

Imports the rest of teamenv (tournaments, match runner) lazily; never imports ``strategy``
(a team's search space is read from its config dataclass's field metadata, declared with
``teamenv.optimize.search_space``). This file imports nothing, so a team's config module can
import the search-space declarations cheaply.
"""
