#!/usr/bin/env bash
# Checks the Unity package's scripts and its sample (bindings/csharp/unity) without Unity:
#   1. the HLSL of each Samples~/*/*.shader (its CGPROGRAM block) compiles with glslang's HLSL
#      front end (Debian: glslang-tools), UnityCG.cginc replaced by stubs of what the shaders use;
#   2. every Runtime/*.cs (the UnityEngine glue: PbfUnity.cs, PbfFloatingBody.cs, ...) and every
#      sample's .cs compile with mcs against the bindings and tools/unity_stub/UnityEngine.cs
#      (stand-ins with the signatures of the UnityEngine calls they make).
# A syntax and type check only: nothing is drawn or simulated. Ends with
# 'unity sample: N passed, N failed'; exit 1 on a failure, 77 when a tool is missing.
#   bash tools/check_unity_sample.sh
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
unity="bindings/csharp/unity"
for tool in glslangValidator mcs; do
  command -v "$tool" > /dev/null || { echo "check_unity_sample.sh: $tool missing (glslang-tools, mono-mcs)"; exit 77; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0
ok() { echo "  ok    $1"; passed=$((passed + 1)); }
fail() { echo "  FAIL  $1"; failed=$((failed + 1)); }

echo "== Unity scripts and sample (UnityEngine stubs, glslang)"
for shader in "$unity"/Samples~/*/*.shader; do
  {
    echo 'float4x4 UNITY_MATRIX_VP;'
    echo '#define fixed4 float4'
    sed -n '/CGPROGRAM/,/ENDCG/p' "$shader" | sed '1d;$d' | grep -v -E '^\s*#(pragma|include)'
  } > "$tmp/shader.hlsl"
  for stage in vert frag; do
    if glslangValidator -D -V -S "$stage" -e "$stage" -o "$tmp/$stage.spv" "$tmp/shader.hlsl" > "$tmp/log" 2>&1; then
      ok "$(basename "$shader"): $stage program compiles (glslang HLSL)"
    else
      cat "$tmp/log"
      fail "$(basename "$shader"): $stage program"
    fi
  done
done

# The runtime glue alone (what a project gets without importing the sample), then with the samples.
runtime=("$unity"/Runtime/*.cs)
if mcs -langversion:7.2 -target:library -nowarn:1591 -r:System.Numerics -out:"$tmp/runtime.dll" \
     tools/unity_stub/UnityEngine.cs "$unity"/Runtime/Core/*.cs "${runtime[@]}" > "$tmp/mcs.log" 2>&1; then
  ok "Runtime: $(cd "$unity/Runtime" && echo *.cs) compile (mcs, C# 7.2, UnityEngine stubs)"
else
  cat "$tmp/mcs.log"
  fail "Runtime/*.cs"
fi
for sample in "$unity"/Samples~/*/; do
  name="$(basename "$sample")"
  if mcs -langversion:7.2 -target:library -nowarn:1591 -r:System.Numerics -out:"$tmp/$name.dll" \
       tools/unity_stub/UnityEngine.cs "$unity"/Runtime/Core/*.cs "${runtime[@]}" "$sample"*.cs > "$tmp/mcs.log" 2>&1; then
    ok "Samples~/$name: $(cd "$sample" && echo *.cs) compile with the runtime (mcs, C# 7.2, UnityEngine stubs)"
  else
    cat "$tmp/mcs.log"
    fail "Samples~/$name/*.cs"
  fi
done
echo "unity sample: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
