// Draws libpbf particles as instanced meshes (Graphics.DrawMeshInstancedProcedural, or
// DrawMeshInstancedIndirect with the count libpbf writes into the draw arguments): instance i
// reads its position from _PbfPositions[i] (x, y, z, density ratio). A unit-diameter mesh such as
// Unity's built-in sphere is scaled to the particle diameter. Built-in RP and URP (unlit pass).
//
// With _UseAnisotropy = 1 the positions are libpbf's smoothed positions and each sphere is
// stretched into the particle's ellipsoid: _PbfAnisotropy holds 3 float4 per particle (unit axis
// x, y, z, radius in m), longest axis first (PBF_BUFFER_ANISOTROPY, World.CopyAnisotropy). The
// mesh's unit sphere u maps to centre + sum_k a_k r_k u_k; its normals to sum_k a_k n_k / r_k
// (the inverse transpose of that map), so the lighting follows the flattened surface.
//
// With _UseMaterials = 1 each particle takes its fluid material's colour instead of _Color:
// _PbfMaterials holds the particles' material indices (PBF_BUFFER_MATERIALS, World.CopyMaterials:
// one byte per particle, four to a uint, little-endian) and _PbfMaterialColors[k] the colour of
// the material with index k (MaterialDesc.Color, from World.Materials). With _MaterialsFromIds = 1
// (the zero-copy path, where the material bytes do not reach the GPU buffers) the material index
// comes from the particle's stable id in _PbfIds (PBF_BUFFER_IDS) instead: ids are given in
// emission order, so each fluid the scene emitted is a range of ids; range k starts at id
// _PbfIdRangeStarts[k] (ascending; x = 0) and has material _PbfIdRangeMaterials[k] (3 ranges).
Shader "Pbf/Particles"
{
    Properties
    {
        _Color ("Color", Color) = (0.15, 0.45, 0.95, 1)
        _DenseColor ("Compressed colour", Color) = (0.9, 0.95, 1, 1)
        _Radius ("Particle radius", Float) = 0.025
        _UseAnisotropy ("Ellipsoids from _PbfAnisotropy (0 or 1)", Float) = 0
        _UseMaterials ("Colours by material from _PbfMaterials (0 or 1)", Float) = 0
        _MaterialsFromIds ("Materials from _PbfIds and the id ranges (0 or 1)", Float) = 0
        _EllipsoidScale ("Ellipsoid radii times", Float) = 1.25
    }
    SubShader
    {
        Tags { "RenderType" = "Opaque" }
        Pass
        {
            CGPROGRAM
            #pragma vertex vert
            #pragma fragment frag
            #pragma target 4.5
            #include "UnityCG.cginc"

            StructuredBuffer<float4> _PbfPositions;
            StructuredBuffer<float4> _PbfAnisotropy;
            StructuredBuffer<uint> _PbfMaterials;
            StructuredBuffer<uint> _PbfIds;
            float4 _PbfIdRangeStarts;
            float4 _PbfIdRangeMaterials;
            float4 _PbfMaterialColors[8];  // PBF_MAX_MATERIALS
            float4 _Color;
            float4 _DenseColor;
            float _Radius;
            float _UseAnisotropy;
            float _UseMaterials;
            float _MaterialsFromIds;
            float _EllipsoidScale;

            struct appdata
            {
                float4 vertex : POSITION;
                float3 normal : NORMAL;
            };

            struct v2f
            {
                float4 pos : SV_POSITION;
                float3 color : COLOR0;
            };

            v2f vert(appdata v, uint instanceID : SV_InstanceID)
            {
                float4 particle = _PbfPositions[instanceID];
                float3 unit = v.vertex.xyz * 2.0;  // the mesh's unit-diameter sphere as a unit sphere
                float3 world = particle.xyz + unit * _Radius;
                float3 normal = v.normal;
                if (_UseAnisotropy > 0.5)
                {
                    float4 a0 = _PbfAnisotropy[3 * instanceID + 0];
                    float4 a1 = _PbfAnisotropy[3 * instanceID + 1];
                    float4 a2 = _PbfAnisotropy[3 * instanceID + 2];
                    // Radii floored at a tenth of the particle radius: never a degenerate ellipsoid.
                    float3 r = max(float3(a0.w, a1.w, a2.w) * _EllipsoidScale, 0.1 * _Radius);
                    world = particle.xyz + a0.xyz * (unit.x * r.x) + a1.xyz * (unit.y * r.y) + a2.xyz * (unit.z * r.z);
                    normal = normalize(a0.xyz * (v.normal.x / r.x) + a1.xyz * (v.normal.y / r.y) + a2.xyz * (v.normal.z / r.z));
                }
                v2f o;
                o.pos = mul(UNITY_MATRIX_VP, float4(world, 1.0));
                float light = 0.45 + 0.55 * saturate(dot(normal, normalize(float3(0.3, 1.0, 0.2))));
                float compressed = saturate((particle.w - 1.0) * 20.0);
                float3 base = _Color.rgb;
                if (_UseMaterials > 0.5)
                {
                    uint material;
                    if (_MaterialsFromIds > 0.5)
                    {
                        // Range starts are small integers, exact as floats; a rounded large id
                        // still compares above them.
                        float id = (float)_PbfIds[instanceID];
                        material = (uint)(id >= _PbfIdRangeStarts.z ? _PbfIdRangeMaterials.z
                                        : (id >= _PbfIdRangeStarts.y ? _PbfIdRangeMaterials.y : _PbfIdRangeMaterials.x));
                    }
                    else
                    {
                        material = (_PbfMaterials[instanceID >> 2] >> (8 * (instanceID & 3))) & 0xFF;
                    }
                    base = _PbfMaterialColors[min(material, 7u)].rgb;
                }
                o.color = lerp(base, _DenseColor.rgb, compressed) * light;
                return o;
            }

            fixed4 frag(v2f i) : SV_Target { return fixed4(i.color, 1.0); }
            ENDCG
        }
    }
}
