"""One module per editor feature; each has ``register(server)``."""
