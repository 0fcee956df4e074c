// A user-like finger for ccedi: an elliptical section tapering from root to tip, with
// two transverse holes along y (the bending direction), the first so close to the side
// that a thin wall is left (wall = 0.3 mm): the small elements Gmsh puts there set the
// explicit step, as in many a designer's first mesh. Lengths in metres.
// Root face at z = 0 (clamped), tip face at z = L. Mesh: 10-node tetrahedra.
// Read it with `[finger] mesh = "data/fingers/tapered_two_holes.geo"` (ccedi meshes it
// with Gmsh) or mesh it yourself: `gmsh -3 tapered_two_holes.geo`.
SetFactory("OpenCASCADE");

L = 0.1143;                 // length, 4.5 in
root_a = 0.012;             // root semi-axes: a along x, b along y
root_b = 0.00845;
tip_a = 0.008;              // tip semi-axes
tip_b = 0.0056;
hole_1 = 0.003;             // hole radii, at L/3 and 2L/3
hole_2 = 0.0025;
wall = 0.0003;              // the first hole's wall to the side (x) of the finger
a_1 = root_a + (tip_a - root_a) / 3;   // section semi-axis along x at L/3
x_1 = a_1 - hole_1 - wall;             // the first hole's centre, off the axis
h = 0.004;                  // target element size

Ellipse(1) = {0, 0, 0, root_a, root_b};
Curve Loop(1) = {1};
Ellipse(2) = {0, 0, L, tip_a, tip_b};
Curve Loop(2) = {2};
Ruled ThruSections(1) = {1, 2};
Cylinder(2) = {x_1, -2 * root_b, L / 3, 0, 4 * root_b, 0, hole_1};
Cylinder(3) = {0, -2 * root_b, 2 * L / 3, 0, 4 * root_b, 0, hole_2};
BooleanDifference(4) = {Volume{1}; Delete;}{Volume{2, 3}; Delete;};

Physical Volume("finger") = {4};
Mesh.MeshSizeMax = h;
Mesh.MeshSizeMin = 0.0;
Mesh.ElementOrder = 2;
Mesh.SecondOrderLinear = 0;
