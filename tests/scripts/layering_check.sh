#!/usr/bin/env bash
# Architecture rule: no include runs upward. Each layer may include only the
# layers listed for it here (DEVELOPERS.md "Layers").
set -euo pipefail
root=${1:-$(dirname "$0")/../..}
cd "$root"
declare -A allowed=(
  [common]="common"
  [od]="common od"
  [esc]="common esc"
  [pdi_spi]="common esc pdi_spi"
  [pdi_host]="common esc pdi_spi pdi_client pdi_host"
  [coe]="common od esc coe"
  [ds402]="common od esc coe ds402"
  [esi]="common od esi"
  [transport]="common transport"
  [master]="common transport master"
  [slave]="common od esc coe ds402 esi pdi_spi slave"
  [control]="common od esc coe ds402 esi pdi_spi slave control"
  [web]="common od esc coe ds402 esi pdi_spi slave control web"
)
status=0
for layer in "${!allowed[@]}"; do
  [ -d "$layer" ] || continue
  while IFS= read -r line; do
    file=${line%%:*}
    inc=$(sed -E 's/.*#include "([^/"]+)\/.*/\1/' <<<"$line")
    case " ${allowed[$layer]} " in
      *" $inc "*) ;;
      *) echo "layering: $file includes $inc/ (layer $layer may include: ${allowed[$layer]})"; status=1 ;;
    esac
  done < <(grep -rn --include='*.hpp' --include='*.cpp' -E '#include "[^/"]+/' "$layer" | sed -E 's/^([^:]+):[0-9]+:/\1:/')
done
[ $status -eq 0 ] && echo "layering: ok"
exit $status
