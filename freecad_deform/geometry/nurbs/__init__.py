"""B-spline curves and surfaces: exact area and its constraint (Xu, Joneja & Tang), direct
pushes (Yamashita & Fukui, Pratt), fits and folded polylines."""
