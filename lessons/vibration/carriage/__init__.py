"""The air-bearing carriage of §2.3: its model, drawing, derivation steps and claims."""
