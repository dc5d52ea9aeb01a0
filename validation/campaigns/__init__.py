"""Campaigns beside the product path: the speed/accuracy benchmark, the stress run over extreme
inputs and the bad-input catalogue of every public entry point."""
