// Test stub: the declarations of Micro-XRCE-DDS-Client (eProsima, Apache-2.0) that AP_DDS's topic and
// service tables use, as include/uxr/client/core/session/object_id.h and create_entities_bin.h declare them.
#pragma once

#include <cstdint>

#define UXR_DATAWRITER_ID  0x05
#define UXR_DATAREADER_ID  0x06

typedef struct uxrObjectId
{
    uint16_t id;
    uint8_t type;
} uxrObjectId;

typedef enum uxrQoSDurability
{
    UXR_DURABILITY_TRANSIENT_LOCAL = 0,
    UXR_DURABILITY_TRANSIENT,
    UXR_DURABILITY_VOLATILE,
    UXR_DURABILITY_PERSISTENT
} uxrQoSDurability;

typedef enum uxrQoSReliability
{
    UXR_RELIABILITY_RELIABLE = 0,
    UXR_RELIABILITY_BEST_EFFORT,
} uxrQoSReliability;

typedef enum uxrQoSHistory
{
    UXR_HISTORY_KEEP_LAST = 0,
    UXR_HISTORY_KEEP_ALL
} uxrQoSHistory;

typedef struct uxrQoS_t
{
    uxrQoSDurability durability;
    uxrQoSReliability reliability;
    uxrQoSHistory history;
    uint16_t depth;
} uxrQoS_t;
