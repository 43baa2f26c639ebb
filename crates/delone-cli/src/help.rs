//! Help texts.

pub const MAIN: &str = "\
delone — robust Delaunay triangulation (2D) and tetrahedralization (3D)

USAGE:
    delone tri [-SWITCHES] [OPTIONS] FILE[.node]   2D, Triangle's switches
    delone tet [-SWITCHES] [OPTIONS] FILE[.node]   3D, TetGen's switches
    delone adapt IN.mesh --metric IN.sol [-o OUT.mesh] [OPTIONS]
                                                  adapt a mesh to a metric (MMG's options)
    delone --help | --version

Both subcommands read a Triangle/TetGen .node point file and write the
Delaunay mesh next to it, named as Triangle and TetGen name their output
(FILE.node -> FILE.1.node, FILE.1.ele, ...; FILE.1.node -> FILE.2.*).
Switch letters keep the meaning they have in the program each subcommand
stands in for and may be grouped (-zen). `delone tri --help` and
`delone tet --help` list every switch and long option of each.

Every switch is honoured or refused: a switch that would change nothing in
the run asked for (an output switch with -d, -e with tri -r, --cut without
--png, ...) is a usage error naming it and the reason. No output ever
overwrites an input file (the main input or a companion such as .node,
.ele, .poly, .area, .mtr, .weight): such a run is refused before anything
is written. Numbers in switches may use scientific notation (-a1e-3,
-q1.2/1e1); inside a number, e or E belongs to the number only when a
digit, or + or - and a digit, follows; otherwise it is the next switch
(-pq1.2e is -q1.2 then -e; -pq1.2ea1e-3 is -q1.2, -e, -a0.001). Messages
number points, segments and facets as the input file does.

Exit codes: 0 success; 1 input or mesh error (also a refinement stopped
by the -S budget); 2 usage error; 3 the mesh is written (valid,
conforming) but some of its elements miss a bound asked for (-q, -a, -m,
/D), with a message saying how many miss which bound and why;
--warn-unmet makes that a warning and the exit code 0.
";

pub const TRI: &str = "\
delone tri — 2D Delaunay triangulation with Triangle's command line

USAGE:
    delone tri [-SWITCHES] [OPTIONS] FILE[.node]

Reads FILE.node (2D points; `#` comments; numbering from 0 or 1) and writes
FILE.1.node and FILE.1.ele (FILE.2.* if the input is FILE.1.node).

SWITCHES (Triangle letters, may be grouped: -zenC):
    -z   Number all output items from zero (otherwise from the input's first
         index: 1 unless the input starts at 0).
    -e   Also write the edges to FILE.1.edge (boundary marker 1 on the hull).
    -n   Also write the neighbours to FILE.1.neigh (-1 for none).
    -v   Also write the Voronoi diagram (the power diagram with -w) to
         FILE.1.v.node and FILE.1.v.edge (rays: second vertex -1, then
         the direction).
    -w   Regular (weighted Delaunay) triangulation: weights from FILE.weight
         if it exists (header: number of points; then `index weight` or
         `weight` per line), else the first node attribute. Points with
         empty power cells (hidden) are left out of the mesh and reported.
    -N   Do not write the .node file.
    -E   Do not write the .ele file.
    -I   No iteration numbers: write FILE.node / FILE.ele (refused when this
         would overwrite the input).
    -B   No boundary markers in the output .node and .edge files.
    -C   Check the mesh with delone's independent validator and report
         (exit code 1 if it finds a violation; the files are still written).
    -F   Accepted (Triangle: Fortune's sweepline); delone always uses its own
         incremental algorithm (BRIO + Hilbert order, exact predicates).
    -Q   Quiet: no summary, no progress.
    -V   Verbose (repeat for more: -VV): phase details, duplicates by index,
         hull size.
    -h   This help.
    -p   Triangulate a PSLG: FILE.poly (points, segments, holes, regions;
         with no points in it, FILE.node) into its constrained Delaunay
         triangulation; triangles outside the segments and in holes are
         removed (-c keeps the convex hull). An empty result is an error
         saying why (open boundary, no segments, a hole on a segment).
         Writes FILE.1.node, .ele and .poly.
    -q[angle]  With -p: quality mesh, no angle below `angle` degrees (default
         20; up to about 34 terminates in practice; 60 or more is refused:
         no mesh meets it). Triangles left below it (next to smaller input
         angles, as in Triangle; at segments -Y keeps; floating point)
         give exit code 3 and a message counting them by cause
         (--warn-unmet: a warning, exit code 0; -V lists them).
    -a[area]  With -p: no triangle larger than `area`; without a number, the
         regional area bounds of the .poly. Triangles left above it give
         exit code 3 (see -q).
    -S<n>  At most n Steiner points in the refinement. Without -S the budget
         is 2,000,000 + 16 per input point + 2 per triangle -a asks for (at
         most 16.7 M; -V shows it with a memory estimate). When the budget
         stops the refinement before the bounds are met, the mesh reached is
         written, the message names the budget and the triangles left, and
         the exit code is 1.
    -A   With -p: regional attribute per triangle in the .ele file.
    -P   With -p: do not write the .poly file (segments with markers,
         holes, regions).
    -o2  Quadratic triangles: 6 nodes each (corners, then the midpoints of
         the edges opposite corners 1, 2, 3), midpoints appended to the
         .node file; the .vtu gets VTK quadratic triangles (type 22).
    Markers (-p) follow Triangle: a point's own nonzero marker, else that of
    a marked segment through it, else 1 on the boundary, else 0; edges and
    output segments: the segment's nonzero marker, else 1 on the boundary.
    -r   Refine an existing mesh: FILE.node + FILE.ele (+ FILE.poly's
         segments if present; with -a and no number, FILE.area's
         per-triangle bounds); `delone tri -rq30 mesh.1` writes mesh.2.*.
    -D   With -p or -r: conforming Delaunay: subsegments are split (on
         concentric shells) until no vertex lies inside any subsegment's
         diametral circle, so every triangle is truly Delaunay (its
         circumcircle holds no vertex); with -q, -a as well. -C checks it.
    -Y   With -p or -r: no Steiner point on the boundary (segments with a
         triangle on one side only); -YY: none on any segment. Triangles
         that only a boundary split would fix are reported.
    -j   Jettison: the output .node keeps only the vertices of triangles
         (duplicates and points in holes are left out), renumbered;
         .ele, .edge, .poly and .vtu use the new numbers.
    -c   With -p: keep the convex hull (no removal of exterior triangles).
         Without -p: also write the convex hull as segments to FILE.1.poly.
    -u   Refused: a user's triangle test is a closure in the library API
         (delone::tri::refine::refine_with).
    Not implemented yet (error, exit code 2): -g -O -X -i -l -s.

OPTIONS:
    -o FILE.vtu, --vtu FILE.vtu   Also write the mesh as VTK XML (.vtu, binary
                                  appended) with the point markers.
    --vtu-ascii                   Write that .vtu as ASCII (default path
                                  FILE.1.vtu if no -o/--vtu is given).
    --lloyd N                     Move the points by N Lloyd iterations
                                  (centroidal Voronoi) in their bounding box
                                  before meshing; FILE.1.node gets them.
    --threads N                   Threads for quality refinement (default:
                                  the available cores, at most 8). The
                                  mesh is the same for every N.
    --svg FILE.svg                Draw the mesh (and with -v the cells
                                  clipped to the bounding box; hidden
                                  points in red; with -p the segments
                                  thick and the holes as red crosses) as SVG.
    --png FILE.png                The same picture as PNG.
    --png-width N                 Picture width in pixels (default 800).
    --svg-quality                 Colour the triangles by minimum angle
                                  (legend in the corner).
    --stats-json FILE.json        Mesh quality statistics (counts, areas,
                                  edge lengths, angles, angle histogram in
                                  10-degree bins, aspect ratio = longest
                                  edge / shortest altitude, Steiner points
                                  by kind) as JSON; -V prints them.
    --warn-unmet                  With -q or -a: triangles of the mesh
                                  left outside the bounds are a warning
                                  on stderr and the exit code is 0 (else
                                  3). A budget stop (-S) still exits 1.
    --output-dir DIR              Write every output file into DIR.
    --quiet, --verbose, --check   Same as -Q, -V, -C.
    --help, --version

Output .node files keep every input point, numbered as in the input (exact
duplicates are reported and left out of the triangles); markers are the input
markers, or 1 on the convex hull and 0 inside.
";

pub const TET: &str = "\
delone tet — 3D Delaunay tetrahedralization with TetGen's command line

USAGE:
    delone tet [-SWITCHES] [OPTIONS] FILE[.node]

Reads FILE.node (3D points; `#` comments; numbering from 0 or 1) and writes
FILE.1.node, FILE.1.ele and FILE.1.face (convex hull faces), or FILE.2.* if
the input is FILE.1.node.

SWITCHES (TetGen letters, may be grouped: -zfenC):
    -z   Number all output items from zero (otherwise from the input's first
         index: 1 unless the input starts at 0).
    -f   Write all faces (not only the hull) to FILE.1.face (marker 1 on the
         hull, 0 inside).
    -e   Also write the edges to FILE.1.edge (marker 1 on the hull).
    -n   Also write the neighbours to FILE.1.neigh (-1 for none).
    -v   Also write the Voronoi diagram (the power diagram with -w) to
         FILE.1.v.node, .v.edge, .v.face and .v.cell (TetGen's layout).
    -w   Regular (weighted Delaunay) tetrahedralization: weights from
         FILE.weight if it exists (header: number of points; then
         `index weight` or `weight` per line), else the first node
         attribute. Points with empty power cells (hidden) are left out of
         the mesh and reported.
    -k   Also write FILE.1.vtk (legacy ASCII VTK, for ParaView); with -p
         and -r too.
    -N   Do not write the .node file.
    -E   Do not write the .ele file.
    -F   Do not write the .face and .edge files.
    -I   No iteration numbers: write FILE.node / FILE.ele / ... (refused when
         this would overwrite the input).
    -B   No boundary markers in the output .node, .face and .edge files.
    -J   Accepted: delone never removes unused vertices from the output .node.
    -C   Check the mesh with delone's independent validator and report
         (exit code 1 if it finds a violation; the files are still written).
    -Q   Quiet: no summary, no progress.
    -V   Verbose (repeat for more: -VV).
    -h   This help.
    -p   Mesh the inside of a closed PLC or surface: FILE.poly / FILE.smesh
         (TetGen; tried in that order when FILE has no extension), or
         FILE.off/.stl/.ply/.obj/.mesh. Boundary recovery is constrained:
         missing edges and facets are recovered by flips, split by Steiner
         points on them only where flips fail.
         Writes FILE.1.node/.ele/.face (boundary faces and faces on internal
         facets, with facet markers; -f all faces), -e .edge (marker of a
         facet holding the edge, else 0), -n .neigh, -o .vtu;
         -C checks that every facet is a union of mesh faces, orientation,
         adjacency and the volume (regions add up to the enclosed volume).
         Hole points remove their region; region points give attributes;
         facets may divide the inside into several regions.
    -A   With -p: regional attribute of each tetrahedron in the .ele file
         (the region point's; unnamed regions numbered after the largest).
    -c   With -p: keep the tetrahedra outside the surface (convex hull).
         With -q/-a the whole hull is refined: its faces off the surface are
         facets that may be split like input facets; input facets inside
         stay constraints.
    -g   With -p: also write FILE.1.mesh (Medit; references = facet markers
         and region attributes).
    -Y   With -p: no Steiner point on the input surface (interior only);
         an error names the triangles that flips cannot recover. With
         -q/-a the surface is kept as recovered (TetGen's -pqY): no point
         is put on it, a bad tetrahedron whose circumcentre encroaches it
         gets a point inside its circumball that does not, or is left
         (`kept surface` in the refinement line); the volume bound is
         still met everywhere.
    -M   With -p: no merging of coplanar facets. By default edge-adjacent,
         exactly coplanar, consistently oriented triangles of facets with
         the same marker are merged into one facet and re-triangulated
         (Delaunay edges on the plane kept), so edges between them are not
         segments; -M keeps every input triangle as given (also with -Y).
    -q[B][/D] With -p: quality mesh by Delaunay refinement, no tetrahedron
         with a radius-edge ratio above B (default 2.0) — before the
         optimisation, which may raise it (see -O, --keep-ratio); -V reports
         dihedral angles. /D: the dihedral bound in degrees (default 15,
         below 70.5): the optimisation works on the tetrahedra with an angle
         below D or above 180-D first and, on a small mesh where a second
         path may win, twice; -V and
         --stats-json count those left and say what input feature (sharp
         edge, needle or cap triangle) holds each.
         Missed bounds give exit code 3 (--warn-unmet: a warning, exit code
         0) with a message by bound and cause: B counts for the tetrahedra
         the refinement left above it (at sharp input features, small input
         angles) — and with --keep-ratio or -O0 for every tetrahedron of
         the final mesh; the tetrahedra the default optimisation raised
         above B are reported in one line (`N raised above the -q ratio by
         the optimisation`) and do not change the exit code. D counts only
         when given (-q1.414/20): every tetrahedron of the final mesh with
         an angle below D or above 180-D.
    -a[V] With -p: no tetrahedron larger than volume V; with or without a
         number, also the regional volume bounds of the .poly/.smesh (they
         apply only with -a, as in TetGen). Met on every tetrahedron (near
         sharp input too; only an exhausted -S budget leaves some; any
         other left gives exit code 3). The
         line `bounds (final mesh)` counts, on the mesh written, the
         tetrahedra above the -q ratio and above the volume bounds.
    -S<n> At most n Steiner points in the refinement (TetGen's -S). Without
         -S the budget is 500,000 + 16 per input point + 2 per unit of
         volume over the -a bound (at most 4.2 M; -V shows it with a memory
         estimate; a volume bound needing more is refused unless -S is
         given). When the budget stops the refinement, the mesh reached
         is written, the message names the budget and the tetrahedra left,
         and the exit code is 1. -q below sqrt(6)/4 = 0.612 (the regular
         tetrahedron's ratio) is refused: no mesh meets it.
    -m   With -p or -r: sizing (target edge length) from FILE.b.node +
         FILE.b.ele + FILE.b.mtr (background mesh) if they exist, else from
         FILE.mtr (one size per input point; sizes <= 0: no constraint),
         interpolated linearly. No tetrahedron keeps a circumradius above
         0.61 h (the regular tetrahedron of edge h), no boundary triangle
         one above 0.58 h; those left (at sharp input features) give exit
         code 3 (see -q).
    -r   Refine an existing mesh FILE.node + FILE.ele (+ FILE.face markers)
         with -q/-a/-m: its boundary faces, faces between tetrahedra of
         different attributes and listed faces are kept as constraints;
         FILE.1 gives FILE.2.*.
    -O[level] Mesh optimisation after -q/-a (on by default there; -O0 off,
         -O with plain -p optimises the recovered mesh): edge removal,
         multi-face removal, 2-3/3-2/4-4 flips, 2-2 flips within flat
         facets, smoothing, insertion and collapse of interior vertices,
         raising the smallest dihedral-angle sine; the surface keeps its
         shape. Levels: 1 flips, 2 + smoothing, 3 (default) + insertion,
         4 and above the exhaustive polish (every stage keeps going while
         its last half paid, a second run wherever the worst is free, more
         passes and three times the effort budget at -O4).
         -V prints the dihedral angles before and after. The
         optimisation keeps the size bounds (-a, regional, -m); it trades the
         -q radius-edge bound for dihedral angles (slivers have good
         radius-edge ratios; -V reports the largest ratio left): give
         --keep-ratio to keep that bound too (at a cost in dihedral angles),
         or -O0 for the refinement's mesh as it is. Without either, the
         tetrahedra the optimisation raises above the -q ratio are reported
         (one line) but are not a missed bound: the exit code stays 0 for
         them (see -q); with either, every tetrahedron above it counts.
    -d   Only detect self-intersections (exactly): intersecting facet pairs
         and degenerate (zero-area, repeated-point) facets, and for a
         surface (OFF, STL, PLY, OBJ, Medit) its open or non-manifold
         edges (a .poly/.smesh may have both: slits, internal facets);
         nothing is meshed, no file is written (output switches are
         refused). Facets and points are numbered as in the file and in
         -p's messages: .poly/.smesh from their first index, Medit from 1,
         OFF/STL/PLY/OBJ from 0. Exit code 1 when anything is found.
    Not implemented yet (error, exit code 2): -R -i -T -X -D
    -o2 -o/.

OPTIONS:
    -o FILE.vtu, --vtu FILE.vtu   Also write the mesh as VTK XML (.vtu, binary
                                  appended) with the point markers.
    --vtu-ascii                   Write that .vtu as ASCII (default path
                                  FILE.1.vtu if no -o/--vtu is given).
    --threads N                   Threads for reading FILE.node, the
                                  Delaunay insertion of large point sets
                                  (in two spatial parts) and writing
                                  .node/.ele (default: the available
                                  cores, at most 8). The output is the
                                  same for every N.
    --cells-vtu FILE.vtu          Write the Voronoi cells (power cells with
                                  -w) clipped to the points' bounding box as
                                  VTK polyhedra, with the site index.
    --medit FILE.mesh             With -p: write the mesh as Medit .mesh.
    --gmsh FILE.msh               With -p: write the mesh as Gmsh .msh 4.1
                                  (ASCII; physical tags = markers/regions).
    --png FILE.png                A cut-away picture of the mesh: the
                                  tetrahedra on the low side of the cut,
                                  faces exposed by the cut coloured by their
                                  tetrahedron's minimum dihedral angle
                                  (dark red < 5, red < 10, orange < 15,
                                  yellow < 20, light green < 30 degrees,
                                  green above), boundary faces blue-grey.
    --cut x|y|z[=F]|none          The cut: at fraction F (default 0.5) of the
                                  bounding box along the axis (default x).
    --view AZ,EL                  Camera azimuth and elevation in degrees
                                  (default -60,25).
    --png-width N                 Picture width in pixels (default 800;
                                  height 3/4 of it).
    --keep-ratio                  With -q: the optimisation (-O) keeps the
                                  radius-edge bound (see -O).
    --warn-unmet                  With -q, -a or -m: tetrahedra of the mesh
                                  missing a bound (see -q) are a warning on
                                  stderr and the exit code is 0 (else 3).
                                  A budget stop (-S) still exits 1.
    --stats-json FILE.json        Mesh quality statistics (dihedral-angle and
                                  radius-edge histograms, volumes, edges),
                                  Steiner points by kind, the refinement's
                                  cells left above the bound, the
                                  optimisation's before/after, the input's
                                  bounds and the worst tetrahedra left with
                                  the reason.
    --output-dir DIR              Write every output file into DIR.
    --quiet, --verbose, --check   Same as -Q, -V, -C.
    --help, --version

Tetrahedra are written with positive orientation: (b-a)x(c-a).(d-a) > 0.
Hull faces in .face are oriented with their normal pointing out of the mesh.
";
