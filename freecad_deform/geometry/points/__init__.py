"""Point clouds: stretch and sweep of points, their spacing and section bands."""
