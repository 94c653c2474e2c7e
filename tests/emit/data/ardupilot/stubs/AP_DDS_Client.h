// Test stub: the part of ArduPilot's libraries/AP_DDS/AP_DDS_Client.h (commit 003e46bb, GPL-3.0) that
// AP_DDS_Topic_Table.h and AP_DDS_Service_Table.h fill in: the two tables' structs, as declared there.
#pragma once

#include "uxr/client/client.h"

class AP_DDS_Client
{
public:
    //! @brief Enum used to mark a topic as a data reader or writer
    enum class Topic_rw : uint8_t {
        DataReader = 0,
        DataWriter = 1,
    };

    //! @brief Convenience grouping for a single "channel" of data
    struct Topic_table {
        const uint8_t topic_id;
        const uint8_t pub_id;
        const uint8_t sub_id;    // added sub_id fields to avoid confusion
        const uxrObjectId dw_id;
        const uxrObjectId dr_id; // added dr_id fields to avoid confusion
        const Topic_rw topic_rw;
        const char* topic_name;
        const char* type_name;
        const uxrQoS_t qos;
    };
    static const struct Topic_table topics[];

    //! @brief Enum used to mark a service as a requester or replier
    enum class Service_rr : uint8_t {
        Requester = 0,
        Replier = 1,
    };

    //! @brief Convenience grouping for a single "channel" of services
    struct Service_table {
        const uint8_t req_id;
        const uint8_t rep_id;
        const Service_rr service_rr;
        const char* service_name;
        const char* request_type;
        const char* reply_type;
        const char* request_topic_name;
        const char* reply_topic_name;
        const uxrQoS_t qos;
    };
    static const struct Service_table services[];
};
