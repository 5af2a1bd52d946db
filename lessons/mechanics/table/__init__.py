"""Problem 2.5: the work table with six degrees of freedom: model, derivation, played frames."""
