// Row-major 3x3 matrices as the parameter block carries them (three vec4 rows), out = M · v.
#ifndef HDRC_MATRIX_GLSL
#define HDRC_MATRIX_GLSL

vec3 mul_rows(vec4 m[3], vec3 v) { return vec3(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v)); }

#endif
