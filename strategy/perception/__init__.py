"""Perception: the belief (world model) built from an observation, localization, filtering."""
