"""One quadric of every type, with a point on it (the analyzer tests' surfaces)."""

from __future__ import annotations

from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric

#: name -> (quadric, a point on it)
SURFACES = {
    "sphere": (Quadric.sphere(1.0), (1.0, 0.0, 0.0)),
    "ellipsoid": (Quadric.ellipsoid(3.0, 2.0, 1.0), (0.0, 2.0, 0.0)),
    "elliptic-cylinder": (Quadric.elliptic_cylinder(2.0, 1.0), (2.0, 0.0, 0.5)),
    "elliptic-cone": (Quadric.elliptic_cone(1.0, 2.0, 1.0), (1.0, 0.0, 1.0)),
    "elliptic-paraboloid": (Quadric.elliptic_paraboloid(1.0, 2.0), (1.0, 0.0, 1.0)),
    "hyperbolic-paraboloid": (Quadric.hyperbolic_paraboloid(1.0, 1.0), (1.0, 0.0, 1.0)),
    "hyperboloid-1": (Quadric.hyperboloid_one_sheet(1.0, 1.0, 2.0), (1.0, 0.0, 0.0)),
    "hyperboloid-2": (Quadric.hyperboloid_two_sheets(1.0, 1.0, 1.0), (0.0, 0.0, 1.0)),
}
