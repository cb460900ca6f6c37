#version 330 core
// Deferred lighting (paper §3.1, Fig. 1g): every visible pixel shaded once from the G-buffer with
// the unshadowed direct light of the scene's emitters, plus emission and an ambient term for
// infinite emitters. No ray is traced: shadows, reflections and refractions are the ray tracer's.
//
// lights: texture of 3 rows per light (texelFetch(x = light, y = row)):
//   row 0: position (xyz), kind (0 isotropic point, 1 spot, 2 area sample, 3 directional)
//   row 1: axis (spot axis, area normal, directional travel direction), cosine of the spot cutoff
//   row 2: intensity (W/sr; area samples: radiance x area share; directional: irradiance), cos of beam width
uniform sampler2D g_position;
uniform sampler2D g_normal;
uniform sampler2D g_albedo;
uniform sampler2D g_specular;
uniform sampler2D g_optical;
uniform sampler2D g_emission;
uniform sampler2D g_hit;
uniform sampler2D lights;
uniform int light_count;
uniform vec3 ambient;
uniform vec3 eye;

out vec4 out_color;

const float PI = 3.14159265358979;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 emission = texelFetch(g_emission, px, 0).rgb;
    if (texelFetch(g_hit, px, 0).r < 0.5) { out_color = vec4(emission, 1.0); return; }
    vec3 p = texelFetch(g_position, px, 0).xyz;
    vec3 n = normalize(texelFetch(g_normal, px, 0).xyz);
    vec3 albedo = texelFetch(g_albedo, px, 0).rgb;
    vec3 specular = texelFetch(g_specular, px, 0).rgb;
    float roughness = max(texelFetch(g_optical, px, 0).a, 0.05);
    float shininess = 2.0 / (roughness * roughness) - 2.0;  // Blinn-Phong exponent of a GGX alpha
    vec3 v = normalize(eye - p);
    if (dot(n, v) < 0.0) n = -n;  // two-sided shading, as Mitsuba's BSDFs see the front side

    vec3 color = emission + ambient * (albedo + specular);
    for (int k = 0; k < light_count; ++k) {
        vec4 r0 = texelFetch(lights, ivec2(k, 0), 0);
        vec4 r1 = texelFetch(lights, ivec2(k, 1), 0);
        vec4 r2 = texelFetch(lights, ivec2(k, 2), 0);
        int kind = int(r0.w + 0.5);
        vec3 l;
        vec3 irradiance;  // at normal incidence
        if (kind == 3) {
            l = -r1.xyz;
            irradiance = r2.rgb;
        } else {
            vec3 d = r0.xyz - p;
            float dist2 = max(dot(d, d), 1e-8);
            l = d * inversesqrt(dist2);
            float falloff = 1.0;
            if (kind == 1) {  // spot: smooth fall-off between beam width and cutoff, as Mitsuba's spot
                float c = dot(-l, r1.xyz);
                falloff = c < r1.w ? 0.0 : (c >= r2.w ? 1.0 : (acos(r1.w) - acos(c)) / max(acos(r1.w) - acos(r2.w), 1e-6));
            } else if (kind == 2) {  // area sample: cosine emitter on its front side
                falloff = max(dot(-l, r1.xyz), 0.0);
            }
            irradiance = r2.rgb * falloff / dist2;
        }
        float cos_i = dot(n, l);
        if (cos_i <= 0.0) continue;
        vec3 h = normalize(l + v);
        float lobe = (shininess + 8.0) / (8.0 * PI) * pow(max(dot(n, h), 0.0), shininess);
        color += irradiance * cos_i * (albedo / PI + specular * lobe);
    }
    out_color = vec4(color, 1.0);
}
