"""What every layer of :mod:`bem` shares, at the bottom: the input rules and their checks, the
warnings, the contact curve every model returns, the load-path stepper, background threads and
large arrays."""
