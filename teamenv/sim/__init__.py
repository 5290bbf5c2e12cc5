"""The simulation core: pymunk world, referee, perception, one cycle. Knows nothing of
Gymnasium, PettingZoo or pygame (must not import them)."""
