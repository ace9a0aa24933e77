#!/usr/bin/env bash
# Checks the Unity sample (bindings/csharp/unity/Samples~/FluidDemo) without Unity:
#   1. the HLSL of PbfParticles.shader (its CGPROGRAM block) compiles with glslang's HLSL front
#      end (Debian: glslang-tools), UnityCG.cginc replaced by stubs of what the shader uses;
#   2. PbfFluidDemo.cs compiles with mcs against the bindings and tools/unity_stub/UnityEngine.cs
#      (stand-ins with the signatures of the UnityEngine calls the sample makes).
# A syntax and type check only: nothing is drawn. Exit 77 when a tool is missing.
#   bash tools/check_unity_sample.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
demo="bindings/csharp/unity/Samples~/FluidDemo"
for tool in glslangValidator mcs; do
  command -v "$tool" > /dev/null || { echo "check_unity_sample.sh: $tool missing (glslang-tools, mono-mcs)"; exit 77; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
{
  echo 'float4x4 UNITY_MATRIX_VP;'
  echo '#define fixed4 float4'
  sed -n '/CGPROGRAM/,/ENDCG/p' "$demo/PbfParticles.shader" | sed '1d;$d' | grep -v -E '^\s*#(pragma|include)'
} > "$tmp/shader.hlsl"
for stage in vert frag; do
  glslangValidator -D -V -S "$stage" -e "$stage" -o "$tmp/$stage.spv" "$tmp/shader.hlsl" > "$tmp/log" \
    || { cat "$tmp/log"; echo "check_unity_sample.sh: PbfParticles.shader: $stage failed"; exit 1; }
done
echo "check_unity_sample.sh: PbfParticles.shader: vertex and fragment programs compile (glslang HLSL)"
mcs -langversion:7.2 -target:library -nowarn:1591 -r:System.Numerics -out:"$tmp/demo.dll" \
  tools/unity_stub/UnityEngine.cs bindings/csharp/unity/Runtime/Core/*.cs bindings/csharp/unity/Runtime/PbfUnity.cs \
  "$demo/PbfFluidDemo.cs" > "$tmp/mcs.log" 2>&1 || { cat "$tmp/mcs.log"; echo "check_unity_sample.sh: PbfFluidDemo.cs failed"; exit 1; }
echo "check_unity_sample.sh: PbfFluidDemo.cs compiles (mcs, C# 7.2, UnityEngine stubs)"
