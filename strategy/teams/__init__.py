"""Built-in teams, registered as ``teamenv.teams`` entry points in pyproject.toml."""
