// mfcd geometry (gmsh), written by tools/tube_crush_geo.py: a quarter of a thin-walled
// tube (mean radius R, wall t, length L, its axis on z, its ends at z = 0 and z = L) for
// unstructured linear tetrahedra of size h (input/tube_crush.nml, issue 24's Fig. 1
// case). Its flat sides lie on the symmetry planes y = 0 and x = 0. The trigger: over the
// top 2 H (H about a fold's half-wavelength) the wall bulges outwards, its mid-surface at
// R + a (1 - cos(pi s / H)) / 2 (s = L - z, the wall keeping its thickness), in 6 conical
// rings (a Coons patch between two coaxial circles joined by straight lines is the cone
// itself): a small axisymmetric imperfection that starts the first fold at the ram's end
// with an outward lobe, as a concertina fold starts.
// Parser numbers (&body geo_names, geo_values): R, t, L, H, a, h.
If (!Exists(R))
  R = 10.0e-3;
EndIf
If (!Exists(t))
  t = 1.0e-3;
EndIf
If (!Exists(L))
  L = 20.0e-3;
EndIf
If (!Exists(H))
  H = 4.25e-3;
EndIf
If (!Exists(a))
  a = 0.1e-3;
EndIf
If (!Exists(h))
  h = 0.33e-3;
EndIf
z0 = 0;
w0 = 0;
Point(1) = {0, 0, z0, h};
Point(2) = {R + t / 2 + w0, 0, z0, h};
Point(3) = {0, R + t / 2 + w0, z0, h};
Point(4) = {R - t / 2 + w0, 0, z0, h};
Point(5) = {0, R - t / 2 + w0, z0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {4, 1, 5};
Line(3) = {4, 2};
Line(4) = {5, 3};
s1 = 2 * H * 6 / 6;
z1 = L - s1;
w1 = a * (1 - Cos(Pi * s1 / H)) / 2;
Point(11) = {0, 0, z1, h};
Point(12) = {R + t / 2 + w1, 0, z1, h};
Point(13) = {0, R + t / 2 + w1, z1, h};
Point(14) = {R - t / 2 + w1, 0, z1, h};
Point(15) = {0, R - t / 2 + w1, z1, h};
Circle(11) = {12, 11, 13};
Circle(12) = {14, 11, 15};
Line(13) = {14, 12};
Line(14) = {15, 13};
s2 = 2 * H * 5 / 6;
z2 = L - s2;
w2 = a * (1 - Cos(Pi * s2 / H)) / 2;
Point(21) = {0, 0, z2, h};
Point(22) = {R + t / 2 + w2, 0, z2, h};
Point(23) = {0, R + t / 2 + w2, z2, h};
Point(24) = {R - t / 2 + w2, 0, z2, h};
Point(25) = {0, R - t / 2 + w2, z2, h};
Circle(21) = {22, 21, 23};
Circle(22) = {24, 21, 25};
Line(23) = {24, 22};
Line(24) = {25, 23};
s3 = 2 * H * 4 / 6;
z3 = L - s3;
w3 = a * (1 - Cos(Pi * s3 / H)) / 2;
Point(31) = {0, 0, z3, h};
Point(32) = {R + t / 2 + w3, 0, z3, h};
Point(33) = {0, R + t / 2 + w3, z3, h};
Point(34) = {R - t / 2 + w3, 0, z3, h};
Point(35) = {0, R - t / 2 + w3, z3, h};
Circle(31) = {32, 31, 33};
Circle(32) = {34, 31, 35};
Line(33) = {34, 32};
Line(34) = {35, 33};
s4 = 2 * H * 3 / 6;
z4 = L - s4;
w4 = a * (1 - Cos(Pi * s4 / H)) / 2;
Point(41) = {0, 0, z4, h};
Point(42) = {R + t / 2 + w4, 0, z4, h};
Point(43) = {0, R + t / 2 + w4, z4, h};
Point(44) = {R - t / 2 + w4, 0, z4, h};
Point(45) = {0, R - t / 2 + w4, z4, h};
Circle(41) = {42, 41, 43};
Circle(42) = {44, 41, 45};
Line(43) = {44, 42};
Line(44) = {45, 43};
s5 = 2 * H * 2 / 6;
z5 = L - s5;
w5 = a * (1 - Cos(Pi * s5 / H)) / 2;
Point(51) = {0, 0, z5, h};
Point(52) = {R + t / 2 + w5, 0, z5, h};
Point(53) = {0, R + t / 2 + w5, z5, h};
Point(54) = {R - t / 2 + w5, 0, z5, h};
Point(55) = {0, R - t / 2 + w5, z5, h};
Circle(51) = {52, 51, 53};
Circle(52) = {54, 51, 55};
Line(53) = {54, 52};
Line(54) = {55, 53};
s6 = 2 * H * 1 / 6;
z6 = L - s6;
w6 = a * (1 - Cos(Pi * s6 / H)) / 2;
Point(61) = {0, 0, z6, h};
Point(62) = {R + t / 2 + w6, 0, z6, h};
Point(63) = {0, R + t / 2 + w6, z6, h};
Point(64) = {R - t / 2 + w6, 0, z6, h};
Point(65) = {0, R - t / 2 + w6, z6, h};
Circle(61) = {62, 61, 63};
Circle(62) = {64, 61, 65};
Line(63) = {64, 62};
Line(64) = {65, 63};
s7 = 2 * H * 0 / 6;
z7 = L - s7;
w7 = a * (1 - Cos(Pi * s7 / H)) / 2;
Point(71) = {0, 0, z7, h};
Point(72) = {R + t / 2 + w7, 0, z7, h};
Point(73) = {0, R + t / 2 + w7, z7, h};
Point(74) = {R - t / 2 + w7, 0, z7, h};
Point(75) = {0, R - t / 2 + w7, z7, h};
Circle(71) = {72, 71, 73};
Circle(72) = {74, 71, 75};
Line(73) = {74, 72};
Line(74) = {75, 73};
Curve Loop(1) = {3, 1, -4, -2};
Plane Surface(1) = {1};
Curve Loop(2) = {73, 71, -74, -72};
Plane Surface(2) = {2};
Line(5) = {2, 12};
Line(6) = {3, 13};
Line(7) = {4, 14};
Line(8) = {5, 15};
Curve Loop(101) = {1, 6, -11, -5};
Surface(101) = {101};
Curve Loop(102) = {2, 8, -12, -7};
Surface(102) = {102};
Curve Loop(103) = {3, 5, -13, -7};
Plane Surface(103) = {103};
Curve Loop(104) = {4, 6, -14, -8};
Plane Surface(104) = {104};
Line(15) = {12, 22};
Line(16) = {13, 23};
Line(17) = {14, 24};
Line(18) = {15, 25};
Curve Loop(111) = {11, 16, -21, -15};
Surface(111) = {111};
Curve Loop(112) = {12, 18, -22, -17};
Surface(112) = {112};
Curve Loop(113) = {13, 15, -23, -17};
Plane Surface(113) = {113};
Curve Loop(114) = {14, 16, -24, -18};
Plane Surface(114) = {114};
Line(25) = {22, 32};
Line(26) = {23, 33};
Line(27) = {24, 34};
Line(28) = {25, 35};
Curve Loop(121) = {21, 26, -31, -25};
Surface(121) = {121};
Curve Loop(122) = {22, 28, -32, -27};
Surface(122) = {122};
Curve Loop(123) = {23, 25, -33, -27};
Plane Surface(123) = {123};
Curve Loop(124) = {24, 26, -34, -28};
Plane Surface(124) = {124};
Line(35) = {32, 42};
Line(36) = {33, 43};
Line(37) = {34, 44};
Line(38) = {35, 45};
Curve Loop(131) = {31, 36, -41, -35};
Surface(131) = {131};
Curve Loop(132) = {32, 38, -42, -37};
Surface(132) = {132};
Curve Loop(133) = {33, 35, -43, -37};
Plane Surface(133) = {133};
Curve Loop(134) = {34, 36, -44, -38};
Plane Surface(134) = {134};
Line(45) = {42, 52};
Line(46) = {43, 53};
Line(47) = {44, 54};
Line(48) = {45, 55};
Curve Loop(141) = {41, 46, -51, -45};
Surface(141) = {141};
Curve Loop(142) = {42, 48, -52, -47};
Surface(142) = {142};
Curve Loop(143) = {43, 45, -53, -47};
Plane Surface(143) = {143};
Curve Loop(144) = {44, 46, -54, -48};
Plane Surface(144) = {144};
Line(55) = {52, 62};
Line(56) = {53, 63};
Line(57) = {54, 64};
Line(58) = {55, 65};
Curve Loop(151) = {51, 56, -61, -55};
Surface(151) = {151};
Curve Loop(152) = {52, 58, -62, -57};
Surface(152) = {152};
Curve Loop(153) = {53, 55, -63, -57};
Plane Surface(153) = {153};
Curve Loop(154) = {54, 56, -64, -58};
Plane Surface(154) = {154};
Line(65) = {62, 72};
Line(66) = {63, 73};
Line(67) = {64, 74};
Line(68) = {65, 75};
Curve Loop(161) = {61, 66, -71, -65};
Surface(161) = {161};
Curve Loop(162) = {62, 68, -72, -67};
Surface(162) = {162};
Curve Loop(163) = {63, 65, -73, -67};
Plane Surface(163) = {163};
Curve Loop(164) = {64, 66, -74, -68};
Plane Surface(164) = {164};
Surface Loop(1) = {1, 2, 101, 102, 103, 104, 111, 112, 113, 114, 121, 122, 123, 124, 131, 132, 133, 134, 141, 142, 143, 144, 151, 152, 153, 154, 161, 162, 163, 164};
Volume(1) = {1};
