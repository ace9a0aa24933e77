/* GLSL of the screen-space surface (render_surface.c). Eye space throughout: the camera at the
 * origin looking down -z; "depth" textures hold the eye-space z (negative), 0 where no fluid. */
#ifndef PBF_RENDER_SURFACE_SHADERS_H
#define PBF_RENDER_SURFACE_SHADERS_H

/* The eye-space ray through this pixel (not normalised, z = -1). */
#define GLSL_PIXEL_RAY                                                 \
    "vec3 pixel_ray(vec2 frag, vec2 viewport, mat4 proj) {\n"          \
    "    vec2 ndc = frag / viewport * 2.0 - 1.0;\n"                    \
    "    return vec3(ndc.x / proj[0][0], ndc.y / proj[1][1], -1.0);\n" \
    "}\n"

/* The world around the water, in world space: a gradient sky with a sun, and a checker floor
 * at y = 0 (10 cm squares) that fades into the haze. */
#define GLSL_ENVIRONMENT                                                                     \
    "vec3 sky(vec3 d) {\n"                                                                   \
    "    float up = clamp(d.y, 0.0, 1.0);\n"                                                 \
    "    vec3 c = mix(vec3(0.78, 0.84, 0.90), vec3(0.28, 0.46, 0.72), pow(up, 0.6));\n"      \
    "    float sun = max(dot(d, normalize(vec3(0.4, 0.9, 0.3))), 0.0);\n"                    \
    "    return c + vec3(1.0, 0.95, 0.85) * pow(sun, 300.0) * 4.0;\n"                        \
    "}\n"                                                                                    \
    "vec3 environment(vec3 origin, vec3 d) {\n"                                              \
    "    if (d.y >= -1e-4 || origin.y <= 0.0) return sky(d);\n"                              \
    "    vec3 p = origin + d * (-origin.y / d.y);\n"                                         \
    "    vec2 cell = floor(p.xz / 0.1);\n"                                                   \
    "    float checker = mod(cell.x + cell.y, 2.0);\n"                                       \
    "    vec3 floor_color = mix(vec3(0.62, 0.60, 0.56), vec3(0.86, 0.84, 0.80), checker);\n" \
    "    float haze = 1.0 - exp(-0.12 * length(p - origin));\n"                              \
    "    return mix(floor_color, sky(vec3(d.x, 0.0, d.z)), haze);\n"                         \
    "}\n"

static const char* kFullscreenVertexShader =
    "#version 430 core\n"
    "void main() {\n"
    "    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);\n"
    "    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n"
    "}\n";

static const char* kBackgroundFragmentShader =
    "#version 430 core\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "uniform vec2 u_viewport;\n"
    "uniform vec3 u_eye;\n"
    "out vec4 o_color;\n" GLSL_PIXEL_RAY GLSL_ENVIRONMENT
    "void main() {\n"
    "    vec3 d = transpose(mat3(u_view)) * pixel_ray(gl_FragCoord.xy, u_viewport, u_proj);\n"
    "    o_color = vec4(environment(u_eye, normalize(d)), 1.0);\n"
    "}\n";

/* Ellipsoid splats: a point sprite over each particle's ellipsoid; the fragment shader hits the
 * ellipsoid with the pixel's ray. The anisotropy rows give the ellipsoid x^T M^-1 x = 1 with
 * M = sum r_k^2 a_k a_k^T, i.e. |T x| = 1 where T's rows are a_k / r_k (in eye space). */
#define GLSL_SPLAT_VERTEX                                                                                     \
    "layout(location = 0) in vec4 a_center;  // smoothed position, density ratio\n"                           \
    "layout(location = 1) in vec4 a_axis0;   // unit axis, radius (m), longest first\n"                       \
    "layout(location = 2) in vec4 a_axis1;\n"                                                                 \
    "layout(location = 3) in vec4 a_axis2;\n"                                                                 \
    "uniform mat4 u_view;\n"                                                                                  \
    "uniform mat4 u_proj;\n"                                                                                  \
    "uniform float u_scale;\n"                                                                                \
    "uniform float u_min_radius;\n"                                                                           \
    "uniform float u_viewport_height;\n"                                                                      \
    "flat out vec3 v_center;\n"                                                                               \
    "flat out mat3 v_to_unit;\n"                                                                              \
    "void main() {\n"                                                                                         \
    "    mat3 v = mat3(u_view);\n"                                                                            \
    "    vec3 r = max(vec3(a_axis0.w, a_axis1.w, a_axis2.w) * u_scale, vec3(u_min_radius));\n"                \
    "    v_to_unit = transpose(mat3(v * a_axis0.xyz / r.x, v * a_axis1.xyz / r.y, v * a_axis2.xyz / r.z));\n" \
    "    vec4 eye = u_view * vec4(a_center.xyz, 1.0);\n"                                                      \
    "    v_center = eye.xyz;\n"                                                                               \
    "    gl_Position = u_proj * eye;\n"                                                                       \
    "    // the bounding sphere's diameter in pixels, with a margin for the perspective\n"                    \
    "    gl_PointSize = 1.3 * u_viewport_height * u_proj[1][1] * max(r.x, max(r.y, r.z)) / gl_Position.w;\n"  \
    "    SET_MATERIAL\n"                                                                                      \
    "}\n"
static const char* kSplatVertexShader = "#version 430 core\n#define SET_MATERIAL\n" GLSL_SPLAT_VERTEX;
/* The same splats with the particle's material (render_materials.c): its id (location 4) picks
 * its material index in the table, which picks the material's optics. */
static const char* kSplatMaterialVertexShader =
    "#version 430 core\n"
    "layout(location = 4) in uint a_id;\n"
    "uniform usamplerBuffer u_material_of_id;\n"
    "uniform vec3 u_material_absorption[8];\n"
    "uniform vec3 u_material_deep[8];\n"
    "flat out vec3 v_absorption;\n"
    "flat out vec3 v_deep;\n"
    "#define SET_MATERIAL uint m = min(texelFetch(u_material_of_id, int(a_id)).r, 7u); "
    "v_absorption = u_material_absorption[m]; v_deep = u_material_deep[m];\n" GLSL_SPLAT_VERTEX;

/* The ray p = t d meets |T (p - c)| = 1 where A t^2 - 2 B t + C = 0. */
#define GLSL_SPLAT_HIT                                                     \
    "flat in vec3 v_center;\n"                                             \
    "flat in mat3 v_to_unit;\n"                                            \
    "uniform mat4 u_proj;\n"                                               \
    "uniform vec2 u_viewport;\n" GLSL_PIXEL_RAY                            \
    "bool hit(out vec3 p, out float chord) {\n"                            \
    "    vec3 d = pixel_ray(gl_FragCoord.xy, u_viewport, u_proj);\n"       \
    "    vec3 td = v_to_unit * d, tc = v_to_unit * v_center;\n"            \
    "    float a = dot(td, td), b = dot(td, tc), c = dot(tc, tc) - 1.0;\n" \
    "    float disc = b * b - a * c;\n"                                    \
    "    if (disc <= 0.0) return false;\n"                                 \
    "    float s = sqrt(disc);\n"                                          \
    "    p = d * ((b - s) / a);\n"                                         \
    "    chord = 2.0 * s / a * length(d);\n"                               \
    "    return true;\n"                                                   \
    "}\n"

static const char* kSplatDepthFragmentShader = "#version 430 core\n" GLSL_SPLAT_HIT
                                               "out float o_depth;\n"
                                               "void main() {\n"
                                               "    vec3 p;\n"
                                               "    float chord;\n"
                                               "    if (!hit(p, chord)) discard;\n"
                                               "    vec4 clip = u_proj * vec4(p, 1.0);\n"
                                               "    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;\n"
                                               "    o_depth = p.z;\n"
                                               "}\n";

/* Thickness: the chord of the pixel's ray through each ellipsoid, summed (additive blending). */
static const char* kSplatThicknessFragmentShader = "#version 430 core\n" GLSL_SPLAT_HIT
                                                   "out float o_thickness;\n"
                                                   "void main() {\n"
                                                   "    vec3 p;\n"
                                                   "    float chord;\n"
                                                   "    if (!hit(p, chord)) discard;\n"
                                                   "    o_thickness = chord;\n"
                                                   "}\n";

/* Several materials: each ellipsoid's chord times its material's absorption (the optical depth
 * along the ray, summed) and times its deep colour (averaged by the composite over the
 * thickness), additively blended into two targets. */
static const char* kSplatMaterialFragmentShader = "#version 430 core\n" GLSL_SPLAT_HIT
                                                  "flat in vec3 v_absorption;\n"
                                                  "flat in vec3 v_deep;\n"
                                                  "layout(location = 0) out vec4 o_optics;\n"
                                                  "layout(location = 1) out vec4 o_tint;\n"
                                                  "void main() {\n"
                                                  "    vec3 p;\n"
                                                  "    float chord;\n"
                                                  "    if (!hit(p, chord)) discard;\n"
                                                  "    o_optics = vec4(v_absorption * chord, chord);\n"
                                                  "    o_tint = vec4(v_deep * chord, chord);\n"
                                                  "}\n";

/* One direction of a separable bilateral filter of the depth (Gaussian in screen distance and
 * in depth difference): the spatial sigma is u_sigma metres seen at the pixel's depth, so near
 * and far water is smoothed alike; the depth term keeps silhouettes from bleeding into what is
 * behind them. Empty pixels (0) are neither smoothed nor sampled. */
static const char* kBlurFragmentShader =
    "#version 430 core\n"
    "uniform sampler2D u_depth;\n"
    "uniform ivec2 u_direction;\n"
    "uniform float u_sigma;        // metres\n"
    "uniform float u_depth_sigma;  // metres\n"
    "uniform float u_pixels_per_metre_at_1m;\n"
    "uniform int u_max_radius;\n"
    "out float o_depth;\n"
    "void main() {\n"
    "    ivec2 px = ivec2(gl_FragCoord.xy), size = textureSize(u_depth, 0);\n"
    "    float z = texelFetch(u_depth, px, 0).r;\n"
    "    if (z == 0.0) { o_depth = 0.0; return; }\n"
    "    float sigma_px = max(u_sigma * u_pixels_per_metre_at_1m / -z, 0.5);\n"
    "    int radius = min(int(ceil(2.0 * sigma_px)), u_max_radius);\n"
    "    float sum = 0.0, weights = 0.0;\n"
    "    for (int i = -radius; i <= radius; ++i) {\n"
    "        float zi = texelFetch(u_depth, clamp(px + u_direction * i, ivec2(0), size - 1), 0).r;\n"
    "        if (zi == 0.0) continue;\n"
    "        float dz = (zi - z) / u_depth_sigma;\n"
    "        float w = exp(-0.5 * float(i * i) / (sigma_px * sigma_px) - 0.5 * dz * dz);\n"
    "        sum += zi * w;\n"
    "        weights += w;\n"
    "    }\n"
    "    o_depth = sum / weights;\n"
    "}\n";

/* Shading. The normal is the cross product of the eye-space position's screen differences,
 * each taken on the side whose depth differs less (so a silhouette does not bend it). Colour:
 * Fresnel (Schlick, F0 = 0.02, water against air) between the reflected environment and the
 * refracted background; the background is looked up offset along the normal, by more where the
 * water is thicker, and attenuated by Beer-Lambert absorption exp(-k thickness) towards a deep
 * water colour; plus a Blinn-Phong highlight of the sun. */
static const char* kCompositeFragmentShader =
    "#version 430 core\n"
    "uniform sampler2D u_background;\n"
    "uniform sampler2D u_depth;\n"
    "uniform sampler2D u_thickness;\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "uniform vec2 u_viewport;\n"
    "uniform vec3 u_eye;\n"
    "uniform vec3 u_absorption;   // 1/m per channel\n"
    "uniform vec3 u_deep_color;\n"
    "uniform float u_refraction;  // screen offset per metre of thickness\n"
    "uniform int u_materials;     // 1: absorption and deep colour per pixel from the material pass\n"
    "uniform sampler2D u_optics;\n"
    "uniform sampler2D u_tint;\n"
    "out vec4 o_color;\n" GLSL_PIXEL_RAY GLSL_ENVIRONMENT
    "vec3 eye_position(ivec2 px) {\n"
    "    float z = texelFetch(u_depth, px, 0).r;\n"
    "    return pixel_ray(vec2(px) + 0.5, u_viewport, u_proj) * -z;\n"
    "}\n"
    "vec3 difference(ivec2 px, ivec2 step, vec3 p) {\n"
    "    ivec2 size = textureSize(u_depth, 0);\n"
    "    ivec2 a = clamp(px + step, ivec2(0), size - 1), b = clamp(px - step, ivec2(0), size - 1);\n"
    "    bool has_a = texelFetch(u_depth, a, 0).r != 0.0, has_b = texelFetch(u_depth, b, 0).r != 0.0;\n"
    "    vec3 forward = eye_position(a) - p, backward = p - eye_position(b);\n"
    "    if (!has_a) return backward;\n"
    "    if (!has_b) return forward;\n"
    "    return abs(forward.z) < abs(backward.z) ? forward : backward;\n"
    "}\n"
    "void main() {\n"
    "    ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "    vec2 uv = gl_FragCoord.xy / u_viewport;\n"
    "    float z = texelFetch(u_depth, px, 0).r;\n"
    "    if (z == 0.0) {\n"
    "        o_color = texture(u_background, uv);\n"
    "        gl_FragDepth = 1.0;\n"
    "        return;\n"
    "    }\n"
    "    vec3 p = eye_position(px);\n"
    "    vec3 n = normalize(cross(difference(px, ivec2(1, 0), p), difference(px, ivec2(0, 1), p)));\n"
    "    vec3 v = normalize(-p);\n"
    "    if (dot(n, v) < 0.0) n = -n;\n"
    "    float thickness = texelFetch(u_thickness, px, 0).r;\n"
    "    mat3 to_world = transpose(mat3(u_view));\n"
    "    float fresnel = 0.02 + 0.98 * pow(1.0 - max(dot(n, v), 0.0), 5.0);\n"
    "    vec3 reflected = environment(u_eye, to_world * reflect(-v, n));\n"
    "    vec2 offset = n.xy * u_refraction * min(thickness, 0.3);\n"
    "    vec3 behind = texture(u_background, clamp(uv + offset, vec2(0.0), vec2(1.0))).rgb;\n"
    "    vec3 transmitted = exp(-u_absorption * thickness), deep = u_deep_color;\n"
    "    if (u_materials != 0) {\n"
    "        vec4 optics = texelFetch(u_optics, px, 0), tint = texelFetch(u_tint, px, 0);\n"
    "        transmitted = exp(-optics.rgb);\n"
    "        deep = tint.a > 0.0 ? tint.rgb / tint.a : u_deep_color;\n"
    "    }\n"
    "    vec3 refracted = behind * transmitted + deep * (vec3(1.0) - transmitted);\n"
    "    vec3 l = mat3(u_view) * normalize(vec3(0.4, 0.9, 0.3));\n"
    "    float highlight = pow(max(dot(n, normalize(l + v)), 0.0), 250.0) * 1.6;\n"
    "    o_color = vec4(mix(refracted, reflected, fresnel) + vec3(highlight), 1.0);\n"
    "    vec4 clip = u_proj * vec4(p, 1.0);\n"
    "    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;\n"
    "}\n";

#endif /* PBF_RENDER_SURFACE_SHADERS_H */
