# Sourced by the scripts that validate written ESIs against the ETG schema.
# Sets the array esi_schemas (EtherCATInfo.xsd files to validate against) and,
# when it is empty, esi_schema_why (the reason, for a skip message).
#   ECAT_ESI_SCHEMAS          a user's choice, colon-separated, used as given
#                             (a path that does not exist fails the validation)
#   ECAT_ESI_SCHEMAS_DEFAULT  the CMake cache variable ECAT_ESI_SCHEMAS (ctest sets it);
#                             without it, 1.14 and 1.17 in ../shared/esi-schema.
#                             Files of the default that are absent are left out.
# shellcheck shell=bash
esi_schemas=()
esi_schema_why=""
if [ -n "${ECAT_ESI_SCHEMAS:-}" ]; then
  IFS=: read -r -a esi_schemas <<< "$ECAT_ESI_SCHEMAS"
else
  _esi_default=${ECAT_ESI_SCHEMAS_DEFAULT:-$1/../shared/esi-schema/EtherCATInfo.xsd:$1/../shared/esi-schema/v1.17/EtherCATInfo.xsd}
  IFS=: read -r -a _esi_candidates <<< "$_esi_default"
  for _esi_f in "${_esi_candidates[@]}"; do
    [ -f "$_esi_f" ] && esi_schemas+=("$_esi_f")
  done
  [ ${#esi_schemas[@]} -gt 0 ] ||
    esi_schema_why="no ETG ESI schema at $_esi_default (set ECAT_ESI_SCHEMAS=/path/EtherCATInfo.xsd[:more])"
  unset _esi_default _esi_candidates _esi_f
fi
