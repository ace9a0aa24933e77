// Draws libpbf particles as instanced meshes (Graphics.DrawMeshInstancedProcedural): instance i
// reads its position from _PbfPositions[i] (x, y, z, density ratio). A unit-diameter mesh such as
// Unity's built-in sphere is scaled to the particle diameter. Built-in RP and URP (unlit pass).
Shader "Pbf/Particles"
{
    Properties
    {
        _Color ("Color", Color) = (0.15, 0.45, 0.95, 1)
        _DenseColor ("Compressed colour", Color) = (0.9, 0.95, 1, 1)
        _Radius ("Particle radius", Float) = 0.025
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
            float4 _Color;
            float4 _DenseColor;
            float _Radius;

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
                float3 world = particle.xyz + v.vertex.xyz * (2.0 * _Radius);
                v2f o;
                o.pos = mul(UNITY_MATRIX_VP, float4(world, 1.0));
                float light = 0.45 + 0.55 * saturate(dot(v.normal, normalize(float3(0.3, 1.0, 0.2))));
                float compressed = saturate((particle.w - 1.0) * 20.0);
                o.color = lerp(_Color.rgb, _DenseColor.rgb, compressed) * light;
                return o;
            }

            fixed4 frag(v2f i) : SV_Target { return fixed4(i.color, 1.0); }
            ENDCG
        }
    }
}
