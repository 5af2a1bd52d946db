"""The lesson kit: the contract every lesson implements and what every lesson uses."""
